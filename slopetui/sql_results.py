"""A read-only statement's results as the faces read them: ``slopetui sql`` and the TUI's
SQL console run the same code (this module; no UI).

    fetched = fetch(engine, ReadQuery(sql), write, limit, start=on_columns)

``slopetui.store.read_query`` owns the mechanism (read-only engine, time limit, cancel);
this module owns what both faces do with it: the statement that returns no rows, the rows
handed out a chunk at a time up to a limit, whether there are more (and, for the console,
how many), the way a value is shown as text, and the one line that says why the database
rejected a statement; and, for a console whose queries run in worker threads, one
statement's outcome as plain data (run_query: done, failed or halted; it never raises)
and one engine shared by the threads (SharedEngine).

    outcome = run_query(engine, ReadQuery(sql), limit)   # QueryDone | QueryFailed | QueryHalted

Light on purpose: ``slopetui --help`` builds the ``sql`` parser, which imports this.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from typing import TYPE_CHECKING

from slopetui.display_text import terminal_safe, terminal_safe_lines
from slopetui.store.read_query import (
    DEFAULT_TIMEOUT_S,
    FETCH_CHUNK,
    QueryCancelled,
    QueryError,
    QueryTimedOut,
    ReadQuery,
    Row,
    Rows,
)

if TYPE_CHECKING:
    from sqlalchemy import Engine


@dataclass
class Fetched:
    """What a statement gave: ``columns`` None when it returns no rows at all; ``count``
    rows handed out; ``more`` when rows were left past the limit, ``rest`` how many (when
    counted; ``count_stopped`` says why counting stopped short, e.g. "timed out after 30
    s")."""

    columns: list[str] | None
    count: int = 0
    more: bool = False
    rest: int = 0
    count_stopped: str | None = None


def fetch(engine: Engine, query: ReadQuery, write: Callable[[list[Row]], None], limit: int,
          *, start: Callable[[list[str]], None] | None = None,
          count_rest: bool = False) -> Fetched:
    """Run the statement; ``start(columns)``, then ``write(chunk)`` for at most ``limit``
    rows (0: all). ``count_rest``: count the rows past the limit without keeping them.
    Raises QueryCancelled, QueryTimedOut or QueryError (read_query).

    The text goes to the database as it is (ReadQuery uses exec_driver_sql, not text(),
    which would read ``:name`` in a time literal or a JSON path as a bind parameter).
    """
    with query.execute(engine) as rows:
        if rows.columns is None:
            return Fetched(None)
        if start is not None:
            start(rows.columns)
        count, more = copy_rows(rows, write, limit)
        fetched = Fetched(rows.columns, count, more)
        if more and count_rest:
            rest, fetched.count_stopped = _count_rest(rows)
            fetched.rest = 1 + rest  # the row fetched to tell that there are more
        return fetched


def copy_rows(rows: Rows, write: Callable[[list[Row]], None], limit: int) -> tuple[int, bool]:
    """Fetch and write at most limit rows (0: all), a chunk at a time; one row past the
    limit is fetched to tell whether there are more. Returns (rows written, more)."""
    count, more = 0, False
    while True:
        want = FETCH_CHUNK if not limit else min(FETCH_CHUNK, limit - count + 1)
        chunk = rows.fetch(want)
        if not chunk:
            break
        if limit and count + len(chunk) > limit:
            chunk, more = chunk[:limit - count], True
        write(chunk)
        count += len(chunk)
        if more:
            break
    return count, more


def _count_rest(rows: Rows) -> tuple[int, str | None]:
    """Count the rows left without keeping them, and say why the count stopped short if it
    did: the rows already read are there, a time-out should not hide them. (The runner's
    chunk: it counted 300,000 rows in 293 ms where chunks of 5000 took 545 ms.)"""
    count = 0
    try:
        while chunk := rows.fetch(FETCH_CHUNK):
            count += len(chunk)
    except QueryTimedOut as exc:
        return count, str(exc)
    return count, None


def error_text(exc: QueryError) -> str:
    """Why the database rejected a statement, on one line: a refused write, or its error.
    Escaped (terminal_safe_lines: PostgreSQL's LINE 1 context keeps its lines): the
    database's message may quote stored text."""
    if exc.refused:
        return f"refused: the store is opened read-only ({terminal_safe_lines(exc.message)})"
    return f"error: {terminal_safe_lines(exc.message)}"


def cell_text(value: object) -> str:
    """A value as text for a screen: NULL for none, floats to 6 significant digits, the
    rest as str, escaped (terminal_safe: a stored name or error may hold an escape
    sequence, which would drive the terminal that shows it)."""
    if value is None:
        return "NULL"
    if isinstance(value, float):
        return f"{value:.6g}"
    return terminal_safe(value)


# -- one statement's outcome, for a console ------------------------------------------------

@dataclass
class QueryDone:
    """A statement ran: its columns, its first rows as the database gave them, and how
    many rows in all (``count_stopped``: why the counting stopped at ``total``, e.g.
    "timed out after 30 s"). ``returns_rows`` False: the statement returns no rows at all."""

    columns: list[str]
    rows: list[Row]
    total: int
    elapsed_s: float
    returns_rows: bool = True
    count_stopped: str | None = None


@dataclass
class QueryFailed:
    """A statement failed: ``message`` is the line to show (error_text); ``refused`` when
    the database refused it as a write."""

    message: str
    refused: bool = False

    @classmethod
    def unexpected(cls, exc: Exception) -> QueryFailed:
        """Any other error, shown with its cause rather than a traceback."""
        return cls(f"error: {type(exc).__name__}: {terminal_safe_lines(str(exc))}")


@dataclass
class QueryHalted:
    """A statement did not finish: ``reason`` is "cancelled" or "timed out after N s"."""

    reason: str
    timed_out: bool


QueryOutcome = QueryDone | QueryFailed | QueryHalted


def run_query(engine: Engine, query: ReadQuery | str, limit: int) -> QueryOutcome:
    """Run one statement through fetch, keeping the first limit rows and counting the
    rest. Never raises on a database error, a cancel or the time limit: a console in a
    worker thread reports the outcome, whatever it is (a str runs with the default time
    limit)."""
    if isinstance(query, str):
        query = ReadQuery(query, DEFAULT_TIMEOUT_S)
    rows: list[Row] = []
    start = time.perf_counter()
    try:
        fetched = fetch(engine, query, rows.extend, limit, count_rest=True)
    except QueryCancelled as exc:
        return QueryHalted(str(exc), timed_out=False)
    except QueryTimedOut as exc:
        return QueryHalted(str(exc), timed_out=True)
    except QueryError as exc:
        return QueryFailed(error_text(exc), exc.refused)
    except Exception as exc:
        return QueryFailed.unexpected(exc)
    elapsed = time.perf_counter() - start
    if fetched.columns is None:
        return QueryDone([], [], 0, elapsed, returns_rows=False)
    return QueryDone(fetched.columns, rows, fetched.count + fetched.rest, elapsed,
                     count_stopped=fetched.count_stopped)


class SharedEngine:
    """One read-only engine for the worker threads of a console: opened by whichever
    asks first, disposed once the console is closed and no worker uses it.

    Not sooner: the engine's pool (one connection per thread) closes connections in use
    too, and a query closed under its feet fails in odd ways (MemoryError from execute,
    "Cannot operate on a closed database").
    """

    def __init__(self, open_engine: Callable[[], Engine]) -> None:
        self._open = open_engine
        self._engine: Engine | None = None
        self._lock = threading.Lock()
        self._users = 0
        self._closed = False

    @contextmanager
    def use(self) -> Iterator[Engine]:
        with self._lock:
            if self._engine is None:
                self._engine = self._open()
            self._users += 1
            engine = self._engine
        try:
            yield engine
        finally:
            with self._lock:
                self._users -= 1
                self._dispose_if_unused()

    def close(self) -> None:
        """No new use is expected: dispose of the engine now, or when its last user ends."""
        with self._lock:
            self._closed = True
            self._dispose_if_unused()

    def _dispose_if_unused(self) -> None:
        """Call with _lock held."""
        if self._closed and self._users == 0 and self._engine is not None:
            self._engine.dispose()
            self._engine = None
