"""One read-only statement with a time limit and cancellation, for ``slopetui sql`` and the
TUI's SQL console alike (this module owns the mechanism; it has no UI).

    query = ReadQuery(sql, timeout_s=30)
    with query.execute(db.read_only_engine()) as rows:
        for chunk in rows.chunks():   # lists of tuples, fetched as they are consumed
            ...

``query.cancel()`` may be called from any thread, and from a signal handler: it only sets
a flag. Whoever is reading ``rows`` then gets ``QueryCancelled`` (or ``QueryTimedOut`` once
the limit is spent, ``QueryError`` when the database rejects the statement).

SQLite: a progress handler, called every PROGRESS_INSTRUCTIONS virtual-machine
instructions, returns non-zero once the flag is set or the deadline passed; SQLite then
aborts the statement and the DB-API raises OperationalError("interrupted"). The limit
counts time spent inside SQLite only, not time the caller spends writing rows out (a
``slopetui sql ... | less`` left open is not "the query taking long").

PostgreSQL: the statement is checked first (``pg_read_guard``: a READ ONLY transaction
still lets a statement signal other backends, take advisory locks, NOTIFY, run a DO
block...); then ``SET LOCAL statement_timeout`` inside the read-only transaction (the server's
clock: it runs from the statement's start, the reader's pace included), and a watcher
thread that calls the psycopg connection's ``cancel()`` once the flag is set. Rows are
streamed (psycopg's ``Cursor.stream``): a client-side cursor would first load the whole
result into memory, and a server-side one (DECLARE) would refuse EXPLAIN and SHOW.
"""

from __future__ import annotations

import itertools
import math
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING, Any

from slopetui.store.pg_read_guard import refusal

if TYPE_CHECKING:
    from sqlalchemy import Engine

# SQLAlchemy is imported when a query runs, not with this module: ``slopetui sql``'s
# parser uses DEFAULT_TIMEOUT_S, and ``slopetui --help`` builds every parser.

#: Default time limit of a query (s). The README's example queries took 0.1-90 ms each
#: on a SQLite store of 102,000 done runs (3 sweeps; best of 3, a loaded 2-core box):
#: 30 s is 300 times the slowest, and short enough that a runaway recursive CTE or cross
#: join is stopped before anyone wonders whether the terminal hung.
DEFAULT_TIMEOUT_S = 30.0

#: SQLite virtual-machine instructions between two calls of the progress handler.
#: Measured (SQLite 3.40, Python 3.11, x86-64; CPU time, best of 15; a recursive CTE
#: counting to 3e5 = 5.1e6 instructions): 10.7 ns an instruction without a handler, and
#: 181 ns a call of ReadQuery._progress (the handler called every 10 instructions: 147
#: against 55 ms). So the overhead is 1.7 % every 1000, 0.17 % every 10_000, 0.02 % every
#: 100_000; at 10_000 a call comes every ~0.11 ms, and Ctrl-C stopped a query 0.7-1.4 ms
#: after the signal (in-process, 5 tries). A single slow instruction (a sort step, a
#: string function on a huge value) can delay it further.
PROGRESS_INSTRUCTIONS = 10_000

#: Rows fetched at a time: per-call costs vanish, and a chunk of wide rows stays a few MB.
#: Measured on SQLite, 300,000 rows of 3 columns through ReadQuery (CPU, best of 12):
#: chunks of 100 in 283 ms, of 500 in 293 ms, of 5000 in 545 ms; one fetchall, which also
#: holds every row, 504 ms.
FETCH_CHUNK = 500

#: How often the PostgreSQL watcher looks at the cancel flag (s): Ctrl-C reaches the
#: server within this, and the idle thread wakes only 20 times a second.
PG_CANCEL_POLL_S = 0.05

#: SQLSTATE of "canceling statement" (statement_timeout and cancel() alike).
PG_QUERY_CANCELED = "57014"
#: libpq's PGRES_COMMAND_OK: a statement prepared, or described.
PG_COMMAND_OK = 1


class QueryStopped(Exception):
    """The query did not finish: cancelled, or out of time."""


class QueryCancelled(QueryStopped):
    def __init__(self) -> None:
        super().__init__("cancelled")


class QueryTimedOut(QueryStopped):
    """Out of time: our limit (``timeout_s``), or None: a PostgreSQL server's own
    statement_timeout (a role's default) when we set none."""

    def __init__(self, timeout_s: float | None) -> None:
        super().__init__(f"timed out after {format_seconds(timeout_s)}" if timeout_s
                         else "timed out by the server's statement_timeout")
        self.timeout_s = timeout_s


class QueryError(Exception):
    """The database rejected or failed the statement; ``refused`` when it refused a write
    (the read-only guards), as opposed to a syntax error or a missing table."""

    def __init__(self, message: str, refused: bool) -> None:
        super().__init__(message)
        self.message = message
        self.refused = refused


def format_seconds(seconds: float) -> str:
    return f"{seconds:g} s"


def parse_timeout(text: str) -> float | None:
    """A time limit as typed: seconds, finite and >= 0; 0 means none (returns None)."""
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not math.isfinite(value) or value < 0:
        raise ValueError(f"must be a number of seconds >= 0 (0 for no limit), got {text!r}")
    return value or None


Row = tuple[Any, ...]


class ReadQuery:
    """One statement, run at most once by ``execute``; ``cancel`` from anywhere."""

    def __init__(self, sql: str, timeout_s: float | None = DEFAULT_TIMEOUT_S) -> None:
        if timeout_s is not None and not (math.isfinite(timeout_s) and timeout_s > 0):
            raise ValueError(f"timeout_s must be > 0 or None, got {timeout_s!r}")
        self.sql = sql
        self.timeout_s = timeout_s
        # Plain attributes, not an Event: cancel() may run in a signal handler, which
        # must not take a lock (it may interrupt the thread that holds it).
        self._cancel_requested = False
        self._timed_out = False
        # Time spent inside the database so far, and the deadline of the current call.
        self._spent_s = 0.0
        self._deadline = math.inf
        # The errors _call translates: SQLAlchemy's wrapper and the driver's own (psycopg
        # raises its own from the raw cursor); set by execute.
        self._wrapped_error: type[Exception] = Exception
        self._driver_error: type[Exception] = Exception

    # -- control -------------------------------------------------------------------------

    def cancel(self) -> None:
        """Ask the query to stop. Safe from any thread and from a signal handler."""
        self._cancel_requested = True

    @property
    def cancel_requested(self) -> bool:
        return self._cancel_requested

    # -- running ---------------------------------------------------------------------------

    @contextmanager
    def execute(self, engine: Engine) -> Iterator[Rows]:
        """Run the statement on a read-only engine; the rows are read inside the block.
        Raises QueryCancelled, QueryTimedOut or QueryError (never a DBAPIError)."""
        from sqlalchemy.exc import DBAPIError

        self._check_cancelled()
        backend = engine.dialect.name
        self._wrapped_error = DBAPIError
        self._driver_error = engine.dialect.loaded_dbapi.Error
        try:
            with engine.connect() as conn, conn.begin():
                raw = conn.connection.dbapi_connection
                if backend == "sqlite":
                    with self._sqlite_guard(raw):
                        result = self._call(conn.exec_driver_sql, self.sql)
                        columns = list(result.keys()) if result.returns_rows else None
                        yield Rows(self, columns, result.fetchmany)
                elif backend == "postgresql":
                    with self._postgres_guard(conn, raw) as (columns, fetch):
                        yield Rows(self, columns, fetch)
                else:
                    raise QueryError(f"read-only queries with a time limit are supported on "
                                     f"SQLite and PostgreSQL, not {backend}", refused=False)
        except DBAPIError as exc:  # opening the connection, SET LOCAL
            raise self._translate(exc.orig or exc) from exc

    def _check_cancelled(self) -> None:
        if self._cancel_requested:
            raise QueryCancelled()

    def _call(self, call: Callable[..., Any], *args: Any) -> Any:
        """Call into the database with the rest of the time budget as the deadline; count
        the time spent there (SQLite's limit excludes the caller's time); translate its
        errors."""
        self._check_cancelled()
        start = time.monotonic()
        if self.timeout_s is not None:
            self._deadline = start + self.timeout_s - self._spent_s
        try:
            return call(*args)
        except self._wrapped_error as exc:
            raise self._translate(exc.orig) from exc  # type: ignore[attr-defined]
        except self._driver_error as exc:
            raise self._translate(exc) from exc
        finally:
            self._deadline = math.inf
            self._spent_s += time.monotonic() - start

    def _progress(self) -> int:
        """SQLite's progress handler: non-zero aborts the statement. Called every
        PROGRESS_INSTRUCTIONS instructions, so it stays two comparisons long."""
        if self._cancel_requested:
            return 1
        if time.monotonic() > self._deadline:
            self._timed_out = True
            return 1
        return 0

    @contextmanager
    def _sqlite_guard(self, raw: Any) -> Iterator[None]:
        raw.set_progress_handler(self._progress, PROGRESS_INSTRUCTIONS)
        try:
            yield
        finally:
            # The connection goes back to the pool: the next query brings its own.
            raw.set_progress_handler(None, 0)

    @contextmanager
    def _postgres_guard(self, conn: Any, raw: Any
                        ) -> Iterator[tuple[list[str] | None, Callable[[int], list[Row]]]]:
        # READ ONLY refuses writes to tables only (pg_read_guard lists what else it lets by)
        why = refusal(self.sql)
        if why is not None:
            raise QueryError(why, refused=True)
        # The statement itself goes through the raw cursor, past SQLAlchemy: make sure
        # the engine's begin hook has made this transaction READ ONLY before it runs.
        if conn.exec_driver_sql("SHOW transaction_read_only").scalar() != "on":
            raise QueryError("the transaction is not read-only; refusing to run", True)
        if self.timeout_s is not None:
            # LOCAL: it ends with this transaction, the pooled connection keeps nothing.
            conn.exec_driver_sql(
                f"SET LOCAL statement_timeout = {max(1, round(self.timeout_s * 1000))}")
        stop = threading.Event()
        watcher = threading.Thread(target=self._watch_postgres, args=(raw, stop),
                                   name="slopetui-sql-cancel", daemon=True)
        watcher.start()
        cursor = raw.cursor()
        stream = cursor.stream(self.sql)
        try:
            first = self._call(next, stream, None)
            if cursor.description is not None:
                columns: list[str] | None = [d.name for d in cursor.description]
            else:
                # a stream that ended before its first row leaves no description behind
                # (psycopg drops the closing result): the statement's columns, described
                # by the server without running it again
                columns = self._call(_described_columns, raw, self.sql)
            pending: list[Row] = [] if first is None else [first]

            def fetch(n: int) -> list[Row]:  # Rows.fetch times and translates it
                rows, pending[:] = pending[:n], []
                rows.extend(itertools.islice(stream, n - len(rows)))
                return rows

            yield columns, fetch
        finally:
            stream.close()  # psycopg cancels a stream left half read
            cursor.close()
            stop.set()
            watcher.join()

    def _watch_postgres(self, raw: Any, stop: threading.Event) -> None:
        while not stop.wait(PG_CANCEL_POLL_S):
            if self._cancel_requested:
                # cancel_safe (psycopg >= 3.2) does not block on a dead server.
                getattr(raw, "cancel_safe", raw.cancel)()
                return

    def _translate(self, error: BaseException) -> Exception:
        """A driver's exception as one of ours: the flags say whether an abort was a
        cancel or the time limit."""
        # here: slopetui.store.database imports SQLAlchemy (the comment above the limit)
        from slopetui.store.database import is_refusal

        if self._cancel_requested:
            return QueryCancelled()
        message = str(error).strip() or type(error).__name__
        if self._timed_out or (getattr(error, "sqlstate", None) == PG_QUERY_CANCELED
                               and "statement timeout" in message):
            return QueryTimedOut(self.timeout_s)
        return QueryError(message, is_refusal(message))


def _described_columns(raw: Any, sql: str) -> list[str] | None:
    """The column names of ``sql`` as PostgreSQL describes it (prepared as the unnamed
    statement, not run); None for a statement that returns no rows at all."""
    pgconn = raw.pgconn
    for step in (lambda: pgconn.prepare(b"", sql.encode(raw.info.encoding)),
                 lambda: pgconn.describe_prepared(b"")):
        result = step()
        if result.status != PG_COMMAND_OK:
            raise QueryError(pgconn.error_message.decode(raw.info.encoding, "replace").strip()
                             or "PostgreSQL could not describe the statement's columns",
                             refused=False)
    if result.nfields == 0:
        return None
    return [result.fname(i).decode(raw.info.encoding) for i in range(result.nfields)]


class Rows:
    """The rows of a running query, fetched in chunks as they are asked for."""

    def __init__(self, query: ReadQuery, columns: list[str] | None,
                 fetchmany: Callable[[int], Any]) -> None:
        self.query = query
        #: Column names; None when the statement returns no rows at all.
        self.columns = columns
        self._fetchmany = fetchmany

    def fetch(self, n: int = FETCH_CHUNK) -> list[Row]:
        """Up to n more rows; [] at the end."""
        if self.columns is None:
            return []
        return [tuple(row) for row in self.query._call(self._fetchmany, n)]

    def chunks(self, size: int = FETCH_CHUNK) -> Iterator[list[Row]]:
        """Every remaining row, size at a time."""
        while chunk := self.fetch(size):
            yield chunk

