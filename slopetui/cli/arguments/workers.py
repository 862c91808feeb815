"""The arguments of ``slopetui workers``."""

from __future__ import annotations

import argparse

from slopetui.cli.arguments import add_db_option


def declare(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "workers", help="the worker pools of the store and what each worker runs",
        description="The worker pools of the store: on this host their pid and uptime, on "
                    "other hosts their workers; for each live worker the run it computes, "
                    "the runs it has done and the age of its last heartbeat. Stop the "
                    "pools of this host with `slopetui worker --stop`.")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    add_db_option(p)
