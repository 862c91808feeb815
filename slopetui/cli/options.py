"""Options and errors shared by the subcommands that use the store."""

from __future__ import annotations

import argparse

from slopetui.store.database import DB_ENV, Database


class UsageError(Exception):
    """Bad input on the command line: printed as ``slopetui CMD: error: ...``, exit 2."""


def add_db_option(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--db", metavar="URL",
                        help=f"SQLAlchemy database URL (default: ${DB_ENV}, else SQLite in "
                             "the user data folder, ~/.local/share/slopetui/slopetui.db)")


def open_db(args: argparse.Namespace) -> Database:
    return Database(args.db)


def sweep_id(text: str) -> int:
    """argparse type for SWEEP arguments."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"SWEEP must be a sweep id (an integer >= 1), "
                                         f"got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"SWEEP must be >= 1, got {value}")
    return value
