"""``slopetui cancel|pause|resume SWEEP`` (``slopetui delete``: slopetui.cli.delete, which
asks first)."""

from __future__ import annotations

import argparse

from slopetui.cli.options import add_db_option, open_db, sweep_arg
from slopetui.display_text import terminal_safe


def register(sub: argparse._SubParsersAction) -> None:
    for name, help_ in (("cancel", "cancel a sweep's queued runs (running ones finish)"),
                        ("pause", "stop handing out a sweep's runs (they stay queued)"),
                        ("resume", "hand out a paused sweep's runs again; a cancelled "
                                   "sweep's cancelled runs are queued again")):
        p = sub.add_parser(name, help=help_, description=help_)
        p.add_argument("sweep", metavar="SWEEP", help="sweep id")
        add_db_option(p)
        p.set_defaults(handler=handle, action=name)


def handle(args: argparse.Namespace) -> int:
    from slopetui.sweeps import control

    sweep = sweep_arg(args.sweep)  # before the database opens
    print(terminal_safe(control.apply(open_db(args), args.action, sweep)))  # a stored status
    return 0
