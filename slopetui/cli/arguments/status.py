"""The arguments of ``slopetui status``."""

from __future__ import annotations

import argparse

from slopetui.cli.arguments import add_db_option


def declare(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("status", help="progress of the sweeps and the live workers",
                       description="Progress per sweep (done/total, runs per minute over the "
                                   "last 10 minutes, or over a finished sweep's whole life, ETA, "
                                   "failures) and the live workers.")
    p.add_argument("sweeps", nargs="*", metavar="SWEEP", help="only these sweeps (ids)")
    p.add_argument("--all", action="store_true", help="also finished and cancelled sweeps")
    p.add_argument("--json", action="store_true", help="machine-readable output")
    add_db_option(p)
