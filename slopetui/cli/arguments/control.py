"""The arguments of ``slopetui cancel``, ``pause`` and ``resume``."""

from __future__ import annotations

import argparse

from slopetui.cli.arguments import add_db_option


def declare(sub: argparse._SubParsersAction) -> None:
    for name, help_ in (("cancel", "cancel a sweep's queued runs (running ones finish)"),
                        ("pause", "stop handing out a sweep's runs (they stay queued)"),
                        ("resume", "hand out a paused sweep's runs again; a cancelled "
                                   "sweep's cancelled runs are queued again")):
        p = sub.add_parser(name, help=help_, description=help_)
        p.add_argument("sweep", metavar="SWEEP", help="sweep id")
        add_db_option(p)
        p.set_defaults(action=name)
