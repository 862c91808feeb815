"""Argument types, errors and the opening of the store, shared by the commands' handlers
(the parser's shared option, ``--db``, is ``slopetui.cli.arguments.add_db_option``).
"""

from __future__ import annotations

import argparse
import math
import sys
from typing import TYPE_CHECKING

from slopetui.json_text import json_text

if TYPE_CHECKING:
    from slopetui.store.database import Database

#: The largest id or count a SQL INTEGER holds (SQLite and PostgreSQL BIGINT): a larger
#: number cannot match anything, and the drivers refuse it with an OverflowError.
MAX_SQL_INT = 2**63 - 1



def say_queued(as_json: bool, what: str, job_id: int, show: str) -> int:
    """The answer of a ``--submit``: ``{"id": N, "status": "queued"}``, or a line saying
    that ``what`` was queued, who computes it, and the command ``show`` that shows it."""
    if as_json:
        print(json_text({"id": job_id, "status": "queued"}))
    else:
        print(f"{what} {job_id} queued: a worker computes it (`slopetui worker`, or the "
              f"application's pool); `{show}` shows it")
    return 0


class UsageError(Exception):
    """Bad input on the command line: printed as ``slopetui CMD: error: ...``, exit 2."""


#: The commands that only read the store: they open a SQLite store this user cannot
#: write read-only (slopetui.store.database), saying so on stderr, rather than refuse it.
READ_COMMANDS = frozenset({"status", "show", "sql", "runs", "export", "workers", "branch",
                           "sweeps", "compare"})


def open_db(args: argparse.Namespace) -> Database:
    # here: `show` reads a SQLite store without SQLAlchemy (slopetui.sweeps.diagram), and
    # uses this module's argument types; the store imports SQLAlchemy
    from slopetui.store.open import open_store
    command = getattr(args, "command", None)
    db = open_store(args.db, read_only_ok=command in READ_COMMANDS)
    if db.read_only is not None:
        print(f"slopetui {command}: {db.read_only}", file=sys.stderr)
    return db


def int_arg(flag: str, text: str, low: int, high: int = MAX_SQL_INT, note: str = "") -> int:
    """An integer argument, or a one-line UsageError naming it and its range. The options
    are read as text for this: argparse's own type errors print the usage too."""
    allowed = f"an integer from {low} to {high}{note}"
    try:
        value = int(text)
    except ValueError:
        raise UsageError(f"{flag} = {text!r} is out of range: allowed {allowed}") from None
    if not low <= value <= high:
        raise UsageError(f"{flag} = {value} is out of range: allowed {allowed}")
    return value


def float_arg(flag: str, text: str, low: float, high: float, note: str = "", *,
              above: bool = False) -> float:
    """A finite number argument from ``low`` (``above``: excluded) to ``high``, or a
    one-line UsageError naming it and its range (see int_arg): NaN, inf, garbage and ""
    are refused alike."""
    allowed = (f"a number above {low:g}, at most {high:g}" if above else
               f"a number from {low:g} to {high:g}") + note
    try:
        value = float(text)
    except ValueError:
        raise UsageError(f"{flag} = {text!r} is out of range: allowed {allowed}") from None
    if not (math.isfinite(value) and low <= value <= high) or (above and value == low):
        raise UsageError(f"{flag} = {text!r} is out of range: allowed {allowed}")
    return value


def sweep_arg(text: str, flag: str = "SWEEP") -> int:
    """A sweep id argument (see int_arg)."""
    return int_arg(flag, text, 1, note=" (a sweep id)")
