"""The arguments of ``slopetui branch``."""

from __future__ import annotations

import argparse

from slopetui.cli.arguments import add_db_option


def declare(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("branch", help="stored continuations of periodic orbits, or one of them",
                       description="Without ID: every stored continuation (status, points, "
                                   "what was found). With ID: its branch point by point, the "
                                   "Hopf point and criticality when it started there, and "
                                   "the bifurcations located on it once it is done.")
    p.add_argument("id", nargs="?", metavar="ID", help="a continuation's id")
    p.add_argument("--plot", action="store_true",
                   help="with ID: draw the branch (amplitude against the parameter, stable "
                        "and unstable orbits apart) instead of listing its points")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    add_db_option(p)
