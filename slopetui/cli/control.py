"""``slopetui cancel|pause|resume SWEEP``."""

from __future__ import annotations

import argparse

from slopetui.cli.options import add_db_option, open_db, sweep_id
from slopetui.sweeps import control


def register(sub: argparse._SubParsersAction) -> None:
    for name, help_ in (("cancel", "cancel a sweep's queued runs (running ones finish)"),
                        ("pause", "stop handing out a sweep's runs (they stay queued)"),
                        ("resume", "hand out a paused sweep's runs again")):
        p = sub.add_parser(name, help=help_, description=help_)
        p.add_argument("sweep", type=sweep_id, metavar="SWEEP", help="sweep id")
        add_db_option(p)
        p.set_defaults(handler=handle, action=name)


def handle(args: argparse.Namespace) -> int:
    db = open_db(args)
    if args.action == "cancel":
        n = control.cancel(db, args.sweep)
        print(f"sweep {args.sweep} cancelled: {n} queued runs cancelled")
    else:
        status = getattr(control, args.action)(db, args.sweep)
        print(f"sweep {args.sweep} is {status}")
    return 0
