"""The arguments of ``slopetui compare``."""

from __future__ import annotations

import argparse

from slopetui.cli.arguments import add_db_option


def declare(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("compare", help="two sweeps' specs side by side",
                       description="Two sweeps' specs side by side, setting by setting (axes, "
                                   "fixed parameters, solver, initial conditions), the "
                                   "settings that differ marked with *; '-' where a spec does "
                                   "not name a setting.")
    p.add_argument("a", metavar="SWEEP_A", help="sweep id")
    p.add_argument("b", metavar="SWEEP_B", help="sweep id")
    p.add_argument("--differences", "-d", action="store_true",
                   help="only the settings that differ")
    p.add_argument("--json", action="store_true",
                   help="machine-readable output: each side's value as stored (a side "
                        "without the setting has no a/b key)")
    add_db_option(p)
