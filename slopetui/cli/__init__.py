"""The ``slopetui`` command line: one module per subcommand, wired here."""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Sequence

from sqlalchemy.exc import SQLAlchemyError

from core import ParameterError
from slopetui import __version__
from slopetui.cli import (
    control,
    db,
    example,
    nblock,
    reproduce,
    run,
    runs,
    show,
    sql,
    status,
    submit,
    worker,
)
from slopetui.cli.options import UsageError
from slopetui.store.database import StoreError, explain
from slopetui.sweeps.control import UnknownSweep
from slopetui.sweeps.spec import SpecError

#: Errors that are the user's input or environment, not a bug: one line, no traceback.
USER_ERRORS = (ParameterError, SpecError, StoreError, UnknownSweep, UsageError)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="slopetui",
        description="Simulate, sweep and classify the mean-field spring-block landslide model. "
                    "Without a COMMAND: open the terminal application.",
    )
    parser.add_argument("--version", action="version", version=f"slopetui {__version__}")
    parser.add_argument("--db", dest="tui_db", metavar="URL",
                        help="with no COMMAND: open the application on this database")
    parser.add_argument("--no-workers", action="store_true",
                        help="with no COMMAND: do not start or attach to a local worker pool")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for module in (run, submit, example, status, show, runs, control, sql, worker, db, nblock,
                   reproduce):
        module.register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:  # the application
        from slopetui.tui.app import run_app
        return run_app(args.tui_db, start_workers=not args.no_workers)
    try:
        return int(args.handler(args))
    except USER_ERRORS as exc:
        print(f"slopetui {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except SQLAlchemyError as exc:
        print(f"slopetui {args.command}: database error: "
              f"{explain(exc, getattr(args, 'db', None))}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # `slopetui ... | head`: the reader left, nothing is wrong
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
