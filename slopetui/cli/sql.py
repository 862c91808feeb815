"""``slopetui sql "SELECT ..."``: read-only queries of the store.

The database refuses writes itself (SQLite opened with mode=ro, query_only and an
authorizer; PostgreSQL in READ ONLY transactions); the text is not parsed here.

The query runs through ``slopetui.store.read_query`` with a time limit (--timeout) and
Ctrl-C cancels it; ``slopetui.sql_results`` reads its rows, as in the TUI's console. Rows
are written as they are fetched, a chunk at a time, so that ``--limit 0`` over a huge
result holds one chunk in memory, not the result.

Stored text is data, so into a file or a pipe ``--csv`` and ``--json`` write it exactly as
stored (JSON escapes control characters itself); on a terminal, where an escape sequence
in a name or an error would drive the terminal, the CSV goes through
``slopetui.display_text``'s sanitiser, and the table (text for reading) always does.

``--out FILE`` writes the rows to a file, CSV or JSON by its extension, whole or not at
all (``slopetui.sql_files``, the writer the application's console saves with).

Exit status: 0 done; 1 the time limit stopped the query (the statement may be fine: give
it more time); 2 bad options, or the database rejected or refused the statement (change
the statement); 130 interrupted (Ctrl-C).
"""

from __future__ import annotations

import argparse
import errno
import os
import signal
import sys
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from types import FrameType

from slopetui.cli.options import UsageError, open_db
from slopetui.display_text import for_terminal, terminal_safe
from slopetui.sql_files import CsvStream, JsonLinesStream, NothingToSave, RowStream, file_format, save
from slopetui.sql_results import Fetched, cell_text, error_text, fetch
from slopetui.store.read_query import (
    DEFAULT_TIMEOUT_S,
    QueryCancelled,
    QueryError,
    QueryTimedOut,
    ReadQuery,
    Row,
    parse_timeout,
)

#: Rows over which the aligned table measures its column widths before it prints; later
#: rows are streamed with those widths (a wider cell shifts the rest of its line, data is
#: never cut). The default --limit fits, so a default table is aligned throughout.
TABLE_WIDTH_ROWS = 1000

EXIT_TIMED_OUT = 1
EXIT_REJECTED = 2
EXIT_INTERRUPTED = 130



# -- output ------------------------------------------------------------------------------

class TableWriter(RowStream):
    """Aligned columns: holds the first TABLE_WIDTH_ROWS rows to measure them, then
    streams; finish() ends with the count."""

    def start(self, columns: list[str]) -> None:
        super().start([terminal_safe(c) for c in columns])  # cell_text escapes the cells
        self.held: list[list[str]] | None = []
        self.widths: list[int] = []

    def write(self, rows: list[Row]) -> None:
        cells = [[cell_text(v) for v in row] for row in rows]
        if self.held is None:
            self._lines(cells)
            return
        self.held.extend(cells)
        if len(self.held) >= TABLE_WIDTH_ROWS:
            self._release()

    def _release(self) -> None:
        held, self.held = self.held or [], None
        self.widths = [max([len(c), *(len(r[i]) for r in held)])
                       for i, c in enumerate(self.columns)]
        self._lines([self.columns, ["-" * w for w in self.widths], *held])

    def _lines(self, cells: list[list[str]]) -> None:
        self.out.write("".join(
            "  ".join(v.ljust(w) for v, w in zip(row, self.widths, strict=True)).rstrip() + "\n"
            for row in cells))

    def stop(self) -> None:
        if self.held is not None:
            self._release()
        super().stop()

    def counted(self, count: int, more: bool) -> None:
        if self.held is not None:
            self._release()
        self.out.write(f"({count} row{'s' if count != 1 else ''}"
                       f"{'; more not shown, see --limit' if more else ''})\n")


# -- Ctrl-C -----------------------------------------------------------------------------

@contextmanager
def cancel_on_sigint(query: ReadQuery) -> Iterator[None]:
    """While the query runs, SIGINT cancels it instead of raising KeyboardInterrupt.

    The handler only sets the query's flag: a handler runs between two bytecodes of the
    main thread, maybe while it holds a lock, so taking one could deadlock. The flag is
    read by SQLite's progress handler (or the PostgreSQL watcher thread), which aborts
    the statement; the interrupted fetch then raises QueryCancelled.
    """
    if threading.current_thread() is not threading.main_thread():
        yield  # signal handlers can only be set from the main thread
        return

    def handler(_signum: int, _frame: FrameType | None) -> None:
        query.cancel()

    previous = signal.signal(signal.SIGINT, handler)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)


# -- the command --------------------------------------------------------------------------

#: How many rows are printed without --limit: a screenful of tables, not a file's worth.
#: A file (--out) gets every row: a file cut at 1000 rows passed for the whole result.
DEFAULT_LIMIT = 1000


def handle(args: argparse.Namespace) -> int:
    if args.limit is None:
        args.limit = 0 if args.out is not None else DEFAULT_LIMIT
    if args.limit < 0:
        raise UsageError(f"--limit must be >= 0, got {args.limit}")
    try:
        timeout_s = (DEFAULT_TIMEOUT_S if args.timeout is None
                     else parse_timeout(args.timeout))
    except ValueError as exc:
        raise UsageError(f"--timeout {exc}") from None
    try:
        fmt = None if args.out is None else file_format(args.out)
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    query = ReadQuery(args.query, timeout_s)
    if fmt is not None:
        return _save(args, query, fmt)
    # CSV is data: raw into a file or a pipe, escaped on a terminal only
    writer: RowStream = (CsvStream(for_terminal(sys.stdout)) if args.csv
                         else (JsonLinesStream if args.json else TableWriter)(sys.stdout))
    engine = open_db(args).read_only_engine()
    try:
        with cancel_on_sigint(query):
            fetched = fetch(engine, query, writer.write, args.limit, start=writer.start)
    except (QueryCancelled, QueryTimedOut, QueryError) as exc:
        if writer.started:
            writer.stop()  # the rows read so far stay printed
        return _report(exc)
    finally:
        engine.dispose()
    if fetched.columns is None:
        print("(no rows: the statement returns nothing)")
        return 0
    if isinstance(writer, TableWriter):
        writer.counted(fetched.count, fetched.more)
    writer.finish()
    return 0


def _save(args: argparse.Namespace, query: ReadQuery, fmt: str) -> int:
    """--out FILE: the rows written whole or not at all (a failed query leaves no file,
    and an older one as it was); one line on stdout says how many, and where."""
    target = Path(os.path.realpath(args.out))
    if target.is_dir():  # refused before the query runs
        raise UsageError(f"--out: cannot write {terminal_safe(args.out)}: "
                         f"{os.strerror(errno.EISDIR)} (allowed: a file in an existing folder)")
    engine = open_db(args).read_only_engine()

    def fill(stream: RowStream) -> Fetched:
        return fetch(engine, query, stream.write, args.limit, start=stream.start)

    try:
        with cancel_on_sigint(query):
            fetched = save(target, fmt, fill)
    except (QueryCancelled, QueryTimedOut, QueryError) as exc:
        return _report(exc, " (nothing written)")
    except NothingToSave as exc:
        print(f"slopetui sql: {exc}: {terminal_safe(args.out)} not written", file=sys.stderr)
        return EXIT_REJECTED
    except OSError as exc:
        raise UsageError(f"--out: cannot write {terminal_safe(args.out)}: "
                         f"{exc.strerror or exc} (allowed: a file in an existing folder "
                         "you can write to)") from None
    finally:
        engine.dispose()
    noun = "row" if fetched.count == 1 else "rows"
    more = "; more not written, see --limit (0 for all)" if fetched.more else ""
    print(f"{fetched.count} {noun} written to {terminal_safe(target)}{more}")
    return 0


def _report(exc: QueryCancelled | QueryTimedOut | QueryError, note: str = "") -> int:
    """One line on stderr (ending in ``note``); the exit status."""
    if isinstance(exc, QueryCancelled):
        print(f"slopetui sql: interrupted{note}", file=sys.stderr)
        return EXIT_INTERRUPTED
    if isinstance(exc, QueryTimedOut):
        hint = " (--timeout S sets the limit; 0 for none)" if exc.timeout_s else ""
        print(f"slopetui sql: {terminal_safe(exc)}{hint}{note}", file=sys.stderr)
        return EXIT_TIMED_OUT
    print(f"slopetui sql: {error_text(exc)}{note}", file=sys.stderr)
    return EXIT_REJECTED
