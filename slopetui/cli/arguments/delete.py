"""The arguments of ``slopetui delete``."""

from __future__ import annotations

import argparse

from slopetui.cli.arguments import add_db_option


def declare(sub: argparse._SubParsersAction) -> None:
    help_ = "delete a sweep and its runs (asks first; refused while runs of it are running)"
    p = sub.add_parser("delete", help=help_, description=help_ + ". Runs of other sweeps "
                       "that copied a result from its runs keep it.")
    p.add_argument("sweep", metavar="SWEEP", help="sweep id")
    p.add_argument("--yes", "-y", action="store_true",
                   help="do not ask (needed when stdin is not a terminal)")
    add_db_option(p)
