"""SQL console: read-only queries over the store, results in a table, with the schema and
the query history at hand.

Queries run on ``Database.read_only_engine()``, so the database itself refuses writes
(as ``slopetui sql`` does); the text is never parsed here. Every database call runs in a
thread worker and reports back with a message; widgets are touched on the UI thread only.

A query runs through ``slopetui.store.read_query.ReadQuery`` and
``slopetui.sql_results.run_query`` (``fetch``, the code ``slopetui sql`` runs: the same
default time limit, the same rows, the same error lines), which says how it ended: done,
failed or halted. The screen cancels it when a new query starts, on ctrl+g, and when the
screen is left or closed. ctrl+s (or the palette, as CSV or JSON) saves the rows shown
through ``slopetui.sql_files``, the writer of ``slopetui sql --out``. The history file is
``slopetui.sql_history``'s; the schema comes from ``slopetui.store.catalog``. This module
keeps the widgets, their events and how values look in a cell.
"""

from __future__ import annotations

import contextlib
from dataclasses import dataclass
from decimal import Decimal
from pathlib import Path
from typing import TYPE_CHECKING, ClassVar

from rich.text import Text
from textual import on, work
from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Horizontal, Vertical
from textual.message import Message
from textual.widgets import (
    DataTable,
    Header,
    OptionList,
    Static,
    TextArea,
    Tree,
)
from textual.widgets.option_list import Option
from textual.widgets.text_area import LanguageDoesNotExist
from textual.worker import get_current_worker

from slopetui import sql_history
from slopetui.display_text import terminal_safe, terminal_safe_lines
from slopetui.duration_text import duration_text
from slopetui.sql_files import save_new_results
from slopetui.sql_history import History
from slopetui.sql_results import (
    QueryDone,
    QueryFailed,
    QueryOutcome,
    SharedEngine,
    cell_text,
    run_query,
)
from slopetui.store.catalog import Column, tables_and_columns
from slopetui.store.read_query import DEFAULT_TIMEOUT_S, ReadQuery
from slopetui.tui.figure_writing import ready_folder
from slopetui.tui.messages import StoreFailed
from slopetui.tui.screens.base import SlopeScreen
from slopetui.tui.widgets.query_editor import QueryEditor
from slopetui.tui.widgets.steady_footer import SteadyFooter

if TYPE_CHECKING:
    from slopetui.store.queries import Engine

#: Rows shown in the table; the rest are counted, not displayed.
DISPLAY_LIMIT = 1000
#: Characters shown of one cell: a traceback in runs.error would make its column
#: hundreds of cells wide.
CELL_CHARS = 120

OPENING = "opening the database…"

EXAMPLE_QUERY = """\
-- Regimes per sweep (ctrl+r runs; the database refuses writes)
SELECT sweep_id, regime, count(*) AS runs FROM runs WHERE status = 'done'
GROUP BY sweep_id, regime ORDER BY sweep_id, runs DESC;
"""


# -- formatting -------------------------------------------------------------------------

def format_cell(value: object) -> Text:
    """One value as the table shows it: ``slopetui sql``'s text (cell_text, control
    characters escaped), NULL dimmed, numbers right-aligned. Unlike the CLI, which prints
    data whole, a cell shows decimals to 6 significant digits as floats, bytes in hex, and
    at most CELL_CHARS characters. A Text, so that brackets in the data (JSON lists) are
    not read as markup."""
    if value is None:
        return Text(cell_text(value), style="dim")
    if isinstance(value, bool):
        return Text(cell_text(value))
    if isinstance(value, Decimal):
        return Text(f"{value:.6g}", justify="right")
    if isinstance(value, (int, float)):
        return Text(cell_text(value), justify="right")
    text = value.hex() if isinstance(value, bytes) else cell_text(value)
    if len(text) > CELL_CHARS:
        text = text[:CELL_CHARS - 1] + "…"
    return Text(text)


def one_line(sql: str, width: int = 80) -> str:
    """A query on one line for the history list (its whitespace collapsed)."""
    flat = " ".join(sql.split())
    return flat if len(flat) <= width else flat[:width - 1] + "…"


# -- messages from the workers ----------------------------------------------------------

@dataclass
class QueryFinished(Message):
    """How a query ended (sql_results.run_query). ``cells``: a result's rows formatted
    for the table, in the worker: 1000 rows of 10 columns take 30-100 ms, a stall on the
    UI thread."""

    query: ReadQuery
    outcome: QueryOutcome
    cells: list[tuple[Text, ...]]


@dataclass
class SchemaLoaded(Message):
    """Tables (and views) of the store with their columns as (name, type, primary key)."""

    tables: list[tuple[str, list[Column]]]


@dataclass
class HistoryLoaded(Message):
    queries: list[str]


# -- the screen --------------------------------------------------------------------------

class SqlScreen(SlopeScreen[None]):
    """Editor on top, status line, results below; schema and history on the right."""

    #: Where the history is kept; tests point it elsewhere.
    HISTORY_PATH: ClassVar[Path] = sql_history.default_path()

    BINDINGS = [
        Binding("ctrl+r,ctrl+enter", "run_query", "Run", id="sql.run"),
        Binding("ctrl+b", "toggle_panel", "Schema/history", id="sql.toggle_panel"),
        Binding("escape", "focus_editor", "Editor", id="sql.focus_editor"),
        # Out of the footer (in the help): at 80 columns it leaves the room for how to
        # leave the editor (widgets.query_editor), which the footer says while it is focused.
        Binding("ctrl+l", "clear", "Clear", id="sql.clear", show=False),
        # Not in the footer (it only matters while a query runs): the status line names it.
        Binding("ctrl+g", "cancel_query", "Cancel query", show=False, id="sql.cancel"),
        # Out of the footer for the same room: the help lists it, and the palette offers
        # CSV and JSON.
        Binding("ctrl+s", "save_results('csv')", "Save results", show=False, id="sql.save"),
    ]

    #: Time limit of a query (s; None for none): the same default as ``slopetui sql``.
    QUERY_TIMEOUT_S: ClassVar[float | None] = DEFAULT_TIMEOUT_S

    def __init__(self, history_path: Path | None = None) -> None:
        super().__init__()
        self.history = History(history_path or self.HISTORY_PATH)
        # The workers' engine, disposed once the screen is gone and no worker uses it.
        self._engine = SharedEngine(self._open_engine)
        self._schema_requested = False
        self._pending: str | None = None
        # The query running now (set and read on the UI thread only).
        self._query: ReadQuery | None = None
        self._status = ""
        # The rows in the table, as the database gave them: what ctrl+s saves.
        self.results: QueryDone | None = None

    def compose(self) -> ComposeResult:
        yield Header()
        with Horizontal(id="sql-body"):
            with Vertical(id="sql-main"):
                editor = QueryEditor.code_editor(EXAMPLE_QUERY, id="sql-editor",
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
        yield SteadyFooter()

    def on_mount(self) -> None:
        editor = self.query_one("#sql-editor", TextArea)
        with contextlib.suppress(LanguageDoesNotExist):  # highlighting needs tree-sitter's SQL
            editor.language = "sql"
        editor.move_cursor(editor.document.end)
        editor.focus()
        self.load_history()
        self.refresh_data()

    def on_unmount(self) -> None:
        self.cancel_running()  # else its thread runs on to the time limit
        self._engine.close()

    def on_screen_suspend(self) -> None:
        # Switching to another mode leaves the console: its query stops. A screen pushed
        # on top (the command palette, an error) keeps this one in the stack: it runs on.
        # (The mode has changed by the time this event is handled.)
        if self not in self.app.screen_stack:
            self.cancel_running()

    def on_screen_resume(self) -> None:
        # The app tells only the active screen that the database is open.
        self.refresh_data()

    def refresh_data(self) -> None:
        """The app calls this once its database is open: load the schema, run a query
        that waited for it."""
        if self.db is None:  # being opened, or it could not be (then: why, and how to retry)
            error = self.app.store_error is not None
            self.set_status(self.app.store_status.plain if error else OPENING,
                            "-error" if error else "-info")
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

    def _open_engine(self) -> Engine:
        """The read-only engine (in the first worker that needs it)."""
        if self.db is None:  # workers start once the store is open
            raise RuntimeError("the database is not open yet")
        return self.db.read_only_engine()

    @work(thread=True, exclusive=True, group="sql")
    def execute(self, query: ReadQuery) -> None:
        worker = get_current_worker()
        outcome: QueryOutcome
        try:
            with self._engine.use() as engine:
                outcome = run_query(engine, query, DISPLAY_LIMIT)
        except Exception as exc:  # e.g. an in-memory SQLite store cannot be reopened
            outcome = QueryFailed.unexpected(exc)
        if worker.is_cancelled:  # a newer query replaced this one
            return
        cells = ([tuple(format_cell(v) for v in row) for row in outcome.rows]
                 if isinstance(outcome, QueryDone) else [])
        self.post_message(QueryFinished(query, outcome, cells))

    @work(thread=True, exclusive=True, group="sql-schema")
    def load_schema(self) -> None:
        try:
            with self._engine.use() as engine:
                tables = tables_and_columns(engine)
        except Exception as exc:
            self.post_message(StoreFailed("load the schema", f"{type(exc).__name__}: {exc}"))
            return
        self.post_message(SchemaLoaded(tables))

    @work(thread=True, exclusive=True, group="sql-history-load")
    def load_history(self) -> None:
        try:
            queries = self.history.read()
        except (OSError, UnicodeDecodeError) as exc:
            self.post_message(StoreFailed("read the query history", str(exc)))
            queries = []
        self.post_message(HistoryLoaded(queries))

    @work(thread=True, group="sql-history-save")
    def save_history(self) -> None:
        try:
            self.history.save()
        except OSError as exc:
            self.post_message(StoreFailed("save the query history", str(exc)))

    # -- messages from the workers --

    @on(QueryFinished)
    def show_outcome(self, finished: QueryFinished) -> None:
        if finished.query is not self._query:  # the outcome of a query since replaced
            return
        self._query = None
        self.query_one("#sql-results", DataTable).clear(columns=True)
        self.results = None
        outcome = finished.outcome
        if isinstance(outcome, QueryDone):
            self.show_results(outcome, finished.cells)
        elif isinstance(outcome, QueryFailed):
            self.set_status(outcome.message, "-error")
        elif outcome.timed_out:
            self.set_status(f"{outcome.reason}; nothing shown", "-error")
        else:
            self.set_status(outcome.reason, "-info")

    def show_results(self, done: QueryDone, cells: list[tuple[Text, ...]]) -> None:
        elapsed = duration_text(done.elapsed_s, fine=True)
        if not done.returns_rows:
            self.set_status(f"the statement returns no rows ({elapsed})", "-done")
            return
        table = self.query_one("#sql-results", DataTable)
        table.add_columns(*(Text(terminal_safe(c)) for c in done.columns))
        table.add_rows(cells)
        self.results = done
        noun = "row" if done.total == 1 else "rows"
        shown = f" (first {len(cells)} shown)" if done.total > len(cells) else ""
        if done.count_stopped:
            self.set_status(f"at least {done.total} {noun}{shown}; counting "
                            f"{done.count_stopped}", "-done")
            return
        self.set_status(f"{done.total} {noun}{shown} in {elapsed}", "-done")

    @on(SchemaLoaded)
    def show_schema(self, loaded: SchemaLoaded) -> None:
        tree = self.query_one("#sql-schema", Tree)
        tree.clear()
        for table, columns in loaded.tables:
            # names and types as escaped Text: any tool that writes the store can name a table
            node = tree.root.add(Text(terminal_safe(table), style="bold"), data=table)
            for name, type_, primary in columns:
                label = Text.assemble(terminal_safe(name), " ",
                                      (terminal_safe(type_.lower()), "dim"),
                                      (" pk", "dim italic") if primary else "")
                node.add_leaf(label, data=name)

    @on(HistoryLoaded)
    def merge_loaded_history(self, loaded: HistoryLoaded) -> None:
        unsaved = self.history.merge_read(loaded.queries)
        self.show_history()
        if unsaved:  # queries run before the file was read
            self.save_history()

    # -- widgets' events --

    @on(OptionList.OptionSelected, "#sql-history")
    def recall(self, event: OptionList.OptionSelected) -> None:
        """Put a query of the history back into the editor."""
        if 0 <= event.option_index < len(self.history.queries):
            editor = self.query_one("#sql-editor", TextArea)
            editor.text = self.history.queries[event.option_index]
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
        if self.db is None:
            self._pending = sql  # refresh_data runs it once the database is open
            self.set_status(OPENING, "-info")
            return
        self.start_query(sql)

    def start_query(self, sql: str) -> None:
        self.cancel_running()  # its worker is replaced too (exclusive): it reports nothing
        self._query = ReadQuery(sql, self.QUERY_TIMEOUT_S)
        self.set_status("running… (ctrl+g cancels)", "-info")
        self.execute(self._query)

    def cancel_running(self) -> None:
        """Stop the running query, if any; its worker then reports "cancelled"."""
        if self._query is not None:
            self._query.cancel()

    def action_cancel_query(self) -> None:
        if self._query is None:
            self.set_status("no query is running", "-info")
        self.cancel_running()

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
        self.results = None
        self.set_status("", "-info")

    def action_save_results(self, fmt: str = "csv") -> None:
        """Write the rows shown, as the database gave them, to a new file (CSV or JSON,
        slopetui.sql_files) in the folder figures go to, off the UI thread; the notice
        names the path."""
        done = self.results
        if done is None:
            self.app.notify("nothing to save: run a query that returns rows first")
            return
        folder = self.app.figure_folder

        def save() -> tuple[Path, int]:
            return save_new_results(ready_folder(folder), fmt, done.columns, done.rows)

        def saved(written: tuple[Path, int]) -> None:
            path, n = written
            part = (f" (the first {n} of {done.total}, as shown; slopetui sql --out FILE "
                    "saves all)" if done.total > n else "")
            self.app.notify_text(f"{n} row{'s' if n != 1 else ''} saved to {path}{part}",
                                 timeout=10)

        self.app.background.start(
            save, group="sql-save", done=saved,
            failed=lambda exc: self.app.notify_text(
                f"could not save the results: {type(exc).__name__}: {exc}", severity="error",
                timeout=10))

    # -- helpers --

    def remember(self, sql: str) -> None:
        can_save = self.history.add(sql)
        self.show_history()
        if can_save:  # else merge_loaded_history saves it
            self.save_history()

    def show_history(self) -> None:
        options = self.query_one("#sql-history", OptionList)
        options.clear_options()
        options.add_options([Option(Text(terminal_safe(one_line(q)), no_wrap=True,
                                         overflow="ellipsis"))
                             for q in self.history.queries])

    def set_status(self, message: str, kind: str) -> None:
        """kind: -info (hints, progress), -done (a result), -error (error or refusal)."""
        self._status = message
        status = self.query_one("#sql-status", Static)
        status.update(Text(terminal_safe_lines(message)))  # it may quote stored text
        status.set_class(kind == "-info", "-info")
        status.set_class(kind == "-done", "-done")
        status.set_class(kind == "-error", "-error")
