"""The ``slopetui`` command line: one module per subcommand, wired here."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from slopetui import __version__
from slopetui.cli import run


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="slopetui",
        description="Simulate, sweep and classify the mean-field spring-block landslide model.",
    )
    parser.add_argument("--version", action="version", version=f"slopetui {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    run.register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help(sys.stderr)
        return 2
    try:
        return int(args.handler(args))
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
