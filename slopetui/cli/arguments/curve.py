"""The arguments of ``slopetui curve``."""

from __future__ import annotations

import argparse

from slopetui.cli.arguments import add_db_option


def declare(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("curve", help="stored curves in two parameters, or one of them",
                       description="Without ID: every stored curve (`continue --param2 ... "
                                   "--submit` queues them): kind, parameters, status, points, "
                                   "what was found. With ID: its points and, once it is done, "
                                   "its codimension-two points.")
    p.add_argument("id", nargs="?", metavar="ID", help="a curve's id")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    add_db_option(p)
