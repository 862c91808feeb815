"""SQL console: read-only queries over the store, results in a table, with the schema and
the query history at hand.

Queries run on ``Database.read_only_engine()``, so the database itself refuses writes
(as ``slopetui sql`` does); the text is never parsed here. Every database call runs in a
thread worker and reports back with a message; widgets are touched on the UI thread only.
"""

from __future__ import annotations

import json
import os
import threading
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from decimal import Decimal
from pathlib import Path
from typing import ClassVar

from platformdirs import user_data_path
from rich.text import Text
from sqlalchemy import Engine, inspect
from sqlalchemy.exc import DBAPIError
from textual import on, work
from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Horizontal, Vertical
from textual.message import Message
from textual.screen import Screen
from textual.widgets import (
    DataTable,
    Footer,
    Header,
    OptionList,
    Static,
    TextArea,
    Tree,
)
from textual.widgets.option_list import Option
from textual.widgets.text_area import LanguageDoesNotExist
from textual.worker import get_current_worker

from slopetui.store.database import is_refusal
from slopetui.tui.messages import StoreFailed

#: Rows shown in the table; the rest are counted, not displayed.
DISPLAY_LIMIT = 1000
#: Characters shown of one cell: a traceback in runs.error would make its column
#: hundreds of cells wide.
CELL_CHARS = 120
#: Queries kept in the history file.
HISTORY_LIMIT = 200
#: Rows fetched at a time while counting the rows beyond DISPLAY_LIMIT.
COUNT_CHUNK = 5000

OPENING = "opening the database…"

EXAMPLE_QUERY = """\
-- Regimes per sweep (ctrl+r runs; the database refuses writes)
SELECT sweep_id, regime, count(*) AS runs FROM runs WHERE status = 'done'
GROUP BY sweep_id, regime ORDER BY sweep_id, runs DESC;
"""


# -- formatting -------------------------------------------------------------------------

def format_cell(value: object) -> Text:
    """One value as the table shows it: NULL dimmed, numbers right-aligned with floats
    to 6 significant digits. A Text, so that brackets in the data (JSON lists) are not
    read as markup."""
    if value is None:
        return Text("NULL", style="dim")
    if isinstance(value, bool):
        return Text(str(value))
    if isinstance(value, (float, Decimal)):
        return Text(f"{value:.6g}", justify="right")
    if isinstance(value, int):
        return Text(str(value), justify="right")
    text = value.hex() if isinstance(value, bytes) else str(value)
    if len(text) > CELL_CHARS:
        text = text[:CELL_CHARS - 1] + "…"
    return Text(text)


def format_elapsed(seconds: float) -> str:
    return f"{seconds * 1000:.0f} ms" if seconds < 1 else f"{seconds:.2f} s"


def one_line(sql: str, width: int = 80) -> str:
    """A query on one line for the history list (its whitespace collapsed)."""
    flat = " ".join(sql.split())
    return flat if len(flat) <= width else flat[:width - 1] + "…"


# -- queries (run in worker threads) -----------------------------------------------------

@dataclass
class QueryDone(Message):
    """A statement ran: its columns, the first rows formatted, and how many rows in all."""

    columns: list[str]
    rows: list[tuple[Text, ...]]
    total: int
    elapsed_s: float
    returns_rows: bool = True


@dataclass
class QueryFailed(Message):
    """A statement failed; ``refused`` when the database refused it as a write."""

    message: str
    refused: bool


def run_query(engine: Engine, sql: str, limit: int = DISPLAY_LIMIT,
              cancelled: Callable[[], bool] = lambda: False) -> QueryDone | QueryFailed:
    """Run one statement and report it; never raises on a database error.

    exec_driver_sql, not text(): text() would read ``:name`` in the query (a time literal,
    a JSON path) as a bind parameter.
    """
    start = time.perf_counter()
    try:
        with engine.connect() as conn:
            result = conn.exec_driver_sql(sql)
            if not result.returns_rows:
                return QueryDone([], [], 0, time.perf_counter() - start, returns_rows=False)
            columns = list(result.keys())
            rows = [tuple(format_cell(v) for v in row) for row in result.fetchmany(limit)]
            total = len(rows)
            if total == limit:
                total += _count_rest(result, cancelled)
    except DBAPIError as exc:
        message = str(exc.orig).strip() or type(exc.orig).__name__
        return QueryFailed(message, is_refusal(message))
    except Exception as exc:  # anything else is shown with its cause, not a traceback
        return QueryFailed(f"{type(exc).__name__}: {exc}", refused=False)
    return QueryDone(columns, rows, total, time.perf_counter() - start)


def _count_rest(result: object, cancelled: Callable[[], bool]) -> int:
    """Count the rows past the displayed ones without keeping them."""
    count = 0
    while not cancelled():
        chunk = result.fetchmany(COUNT_CHUNK)  # type: ignore[attr-defined]
        if not chunk:
            break
        count += len(chunk)
    return count


@dataclass
class SchemaLoaded(Message):
    """Tables (and views) of the store with their columns as (name, type, primary key)."""

    tables: list[tuple[str, list[tuple[str, str, bool]]]]


def load_schema(engine: Engine) -> list[tuple[str, list[tuple[str, str, bool]]]]:
    inspector = inspect(engine)
    names = sorted(inspector.get_table_names()) + sorted(inspector.get_view_names())
    return [(name, [(c["name"], str(c["type"]), bool(c.get("primary_key")))
                    for c in inspector.get_columns(name)]) for name in names]


# -- history -----------------------------------------------------------------------------

def merge_history(*sources: Iterable[str], limit: int = HISTORY_LIMIT) -> list[str]:
    """Queries newest first without repeats (the first occurrence wins), at most limit."""
    seen: set[str] = set()
    merged: list[str] = []
    for source in sources:
        for sql in source:
            sql = sql.strip()
            if sql and sql not in seen:
                seen.add(sql)
                merged.append(sql)
    return merged[:limit]


def read_history(path: Path) -> list[str]:
    """One JSON string per line (a query may span lines); unreadable lines are skipped,
    a missing file is an empty history."""
    try:
        lines = path.read_text(encoding="utf-8").splitlines()
    except FileNotFoundError:
        return []
    queries: list[str] = []
    for line in lines:
        try:
            value = json.loads(line)
        except ValueError:
            continue
        if isinstance(value, str):
            queries.append(value)
    return merge_history(queries)


def write_history(path: Path, queries: list[str]) -> None:
    """Replace the file in one rename, so that a crash never leaves half a history."""
    path.parent.mkdir(parents=True, exist_ok=True, mode=0o700)
    tmp = path.with_name(f"{path.name}.{os.getpid()}.tmp")
    tmp.write_text("".join(json.dumps(q) + "\n" for q in queries), encoding="utf-8")
    os.replace(tmp, path)


@dataclass
class HistoryLoaded(Message):
    queries: list[str]


# -- the screen --------------------------------------------------------------------------

class SqlScreen(Screen[None]):
    """Editor on top, status line, results below; schema and history on the right."""

    #: Where the history is kept; tests point it elsewhere.
    HISTORY_PATH: ClassVar[Path] = user_data_path("slopetui") / "sql_history"

    BINDINGS = [
        Binding("ctrl+r,ctrl+enter", "run_query", "Run", id="sql.run"),
        Binding("ctrl+b", "toggle_panel", "Schema/history", id="sql.toggle_panel"),
        Binding("escape", "focus_editor", "Editor", id="sql.focus_editor"),
        Binding("ctrl+l", "clear", "Clear", id="sql.clear"),
    ]

    def __init__(self, history_path: Path | None = None) -> None:
        super().__init__()
        self.history_path = history_path or self.HISTORY_PATH
        self.history: list[str] = []
        self._history_loaded = False
        # Saves run in threads; the lock makes the last one to write write the newest.
        self._history_lock = threading.Lock()
        self._engine: Engine | None = None
        self._engine_lock = threading.Lock()
        self._schema_requested = False
        self._pending: str | None = None
        self._status = ""

    def compose(self) -> ComposeResult:
        yield Header()
        with Horizontal(id="sql-body"):
            with Vertical(id="sql-main"):
                editor = TextArea.code_editor(EXAMPLE_QUERY, id="sql-editor",
                                              tab_behavior="focus")
                editor.border_title = "query"
                yield editor
                yield Static("", id="sql-status", markup=False)
                yield DataTable(id="sql-results", zebra_stripes=True)
            with Vertical(id="sql-side"):
                tree: Tree[str] = Tree("store", id="sql-schema")
                tree.show_root = False
                tree.auto_expand = False  # enter inserts a name, space opens a table
                tree.border_title = "schema"
                tree.border_subtitle = "⏎ insert · space open"
                yield tree
                history = OptionList(id="sql-history")
                history.border_title = "history"
                yield history
        yield Footer()

    def on_mount(self) -> None:
        editor = self.query_one("#sql-editor", TextArea)
        try:
            editor.language = "sql"  # highlighting when tree-sitter's SQL grammar is there
        except LanguageDoesNotExist:
            pass
        editor.move_cursor(editor.document.end)
        editor.focus()
        self.load_history()
        self.refresh_data()

    def on_unmount(self) -> None:
        if self._engine is not None:
            self._engine.dispose()

    def on_screen_resume(self) -> None:
        # The app tells only the active screen that the database is open.
        self.refresh_data()

    def refresh_data(self) -> None:
        """The app calls this once its database is open: load the schema, run a query
        that waited for it."""
        if self.app.db is None:  # type: ignore[attr-defined]
            self.set_status(OPENING, "-info")
            return
        if not self._schema_requested:
            self._schema_requested = True
            self.query_one("#sql-schema", Tree).root.add_leaf(Text("loading…", style="dim"))
            self.load_schema()
        if self._pending is not None:
            sql, self._pending = self._pending, None
            self.start_query(sql)
        elif self._status in ("", OPENING):  # keep a result or error on later refreshes
            self.set_status("ctrl+r runs the query; the store is opened read-only", "-info")

    # -- engine and workers --

    def read_only_engine(self) -> Engine:
        """The read-only engine, created once (from whichever worker asks first)."""
        with self._engine_lock:
            if self._engine is None:
                self._engine = self.app.db.read_only_engine()  # type: ignore[attr-defined]
            return self._engine

    @work(thread=True, exclusive=True, group="sql")
    def execute(self, sql: str) -> None:
        worker = get_current_worker()
        try:
            engine = self.read_only_engine()
        except Exception as exc:  # e.g. an in-memory SQLite store cannot be reopened
            self.post_message(QueryFailed(f"{type(exc).__name__}: {exc}", refused=False))
            return
        outcome = run_query(engine, sql, DISPLAY_LIMIT, lambda: worker.is_cancelled)
        if not worker.is_cancelled:  # a newer query replaced this one
            self.post_message(outcome)

    @work(thread=True, exclusive=True, group="sql-schema")
    def load_schema(self) -> None:
        try:
            tables = load_schema(self.read_only_engine())
        except Exception as exc:
            self.post_message(StoreFailed("load the schema", f"{type(exc).__name__}: {exc}"))
            return
        self.post_message(SchemaLoaded(tables))

    @work(thread=True, exclusive=True, group="sql-history-load")
    def load_history(self) -> None:
        try:
            queries = read_history(self.history_path)
        except (OSError, UnicodeDecodeError) as exc:
            self.post_message(StoreFailed("read the query history", str(exc)))
            queries = []
        self.post_message(HistoryLoaded(queries))

    @work(thread=True, group="sql-history-save")
    def save_history(self) -> None:
        with self._history_lock:
            try:
                write_history(self.history_path, list(self.history))
            except OSError as exc:
                self.post_message(StoreFailed("save the query history", str(exc)))

    # -- messages from the workers --

    @on(QueryDone)
    def show_results(self, done: QueryDone) -> None:
        table = self.query_one("#sql-results", DataTable)
        table.clear(columns=True)
        elapsed = format_elapsed(done.elapsed_s)
        if not done.returns_rows:
            self.set_status(f"the statement returns no rows ({elapsed})", "-done")
            return
        table.add_columns(*(Text(c) for c in done.columns))
        table.add_rows(done.rows)
        noun = "row" if done.total == 1 else "rows"
        shown = f" (first {len(done.rows)} shown)" if done.total > len(done.rows) else ""
        self.set_status(f"{done.total} {noun}{shown} in {elapsed}", "-done")

    @on(QueryFailed)
    def show_failure(self, failed: QueryFailed) -> None:
        self.query_one("#sql-results", DataTable).clear(columns=True)
        if failed.refused:
            self.set_status(f"refused: the store is opened read-only ({failed.message})",
                            "-error")
        else:
            self.set_status(f"error: {failed.message}", "-error")

    @on(SchemaLoaded)
    def show_schema(self, loaded: SchemaLoaded) -> None:
        tree = self.query_one("#sql-schema", Tree)
        tree.clear()
        for table, columns in loaded.tables:
            node = tree.root.add(Text(table, style="bold"), data=table)
            for name, type_, primary in columns:
                label = Text.assemble(name, " ", (type_.lower(), "dim"),
                                      (" pk", "dim italic") if primary else "")
                node.add_leaf(label, data=name)

    @on(StoreFailed)
    def show_store_failure(self, failed: StoreFailed) -> None:
        failed.stop()  # shown here; the app need not show it again
        self.notify(f"could not {failed.action}: {failed.error}", severity="error", timeout=8)

    @on(HistoryLoaded)
    def merge_loaded_history(self, loaded: HistoryLoaded) -> None:
        ran_already = bool(self.history)
        self.history = merge_history(self.history, loaded.queries)
        self._history_loaded = True
        self.show_history()
        if ran_already:  # queries run before the file was read were not saved yet
            self.save_history()

    # -- widgets' events --

    @on(OptionList.OptionSelected, "#sql-history")
    def recall(self, event: OptionList.OptionSelected) -> None:
        """Put a query of the history back into the editor."""
        if 0 <= event.option_index < len(self.history):
            editor = self.query_one("#sql-editor", TextArea)
            editor.text = self.history[event.option_index]
            editor.move_cursor(editor.document.end)
            editor.focus()

    @on(Tree.NodeSelected, "#sql-schema")
    def insert_name(self, event: Tree.NodeSelected[str]) -> None:
        """Enter on a table or column types its name into the query."""
        if event.node.data:
            editor = self.query_one("#sql-editor", TextArea)
            editor.insert(event.node.data)
            editor.focus()

    # -- actions --

    def action_run_query(self) -> None:
        sql = self.query_one("#sql-editor", TextArea).text.strip()
        if not sql:
            self.set_status("nothing to run: write a query first", "-info")
            return
        self.remember(sql)
        if self.app.db is None:  # type: ignore[attr-defined]
            self._pending = sql  # refresh_data runs it once the database is open
            self.set_status(OPENING, "-info")
            return
        self.start_query(sql)

    def start_query(self, sql: str) -> None:
        self.set_status("running…", "-info")
        self.execute(sql)

    def action_toggle_panel(self) -> None:
        side = self.query_one("#sql-side")
        side.display = not side.display
        if not side.display and self.focused is not None and side in self.focused.ancestors:
            self.query_one("#sql-editor").focus()

    def action_focus_editor(self) -> None:
        self.query_one("#sql-editor").focus()

    def action_clear(self) -> None:
        """Empty the editor and the results."""
        editor = self.query_one("#sql-editor", TextArea)
        editor.clear()
        editor.focus()
        self.query_one("#sql-results", DataTable).clear(columns=True)
        self.set_status("", "-info")

    # -- helpers --

    def remember(self, sql: str) -> None:
        self.history = merge_history([sql], self.history)
        self.show_history()
        if self._history_loaded:  # else merge_loaded_history saves it
            self.save_history()

    def show_history(self) -> None:
        options = self.query_one("#sql-history", OptionList)
        options.clear_options()
        options.add_options([Option(Text(one_line(q), no_wrap=True, overflow="ellipsis"))
                             for q in self.history])

    def set_status(self, message: str, kind: str) -> None:
        """kind: -info (hints, progress), -done (a result), -error (error or refusal)."""
        self._status = message
        status = self.query_one("#sql-status", Static)
        status.update(Text(message))
        status.set_class(kind == "-info", "-info")
        status.set_class(kind == "-done", "-done")
        status.set_class(kind == "-error", "-error")
