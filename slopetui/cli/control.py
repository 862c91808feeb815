"""``slopetui cancel|pause|resume SWEEP`` (``slopetui delete``: slopetui.cli.delete, which
asks first)."""

from __future__ import annotations

import argparse

from slopetui.cli.options import open_db, sweep_arg
from slopetui.display_text import terminal_safe
from slopetui.sweeps import control


def handle(args: argparse.Namespace) -> int:
    sweep = sweep_arg(args.sweep)  # before the database opens
    print(terminal_safe(control.apply(open_db(args), args.action, sweep)))  # a stored status
    return 0
