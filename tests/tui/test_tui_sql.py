"""The SQL console screen, driven by Textual's Pilot at 80x24 over a small store."""

from __future__ import annotations

import asyncio
import json
import logging
import math
import sqlite3
import stat
import threading
import time
from collections.abc import Awaitable, Callable, Iterator
from pathlib import Path

import pytest
from textual.pilot import Pilot
from textual.screen import Screen
from textual.widgets import DataTable, OptionList, Static, TextArea, Tree

from slopetui.sql_history import read_history
from slopetui.sql_results import QueryDone
from slopetui.store.open import open_store
from slopetui.tui.app import SlopeApp
from slopetui.tui.screens import sql as sql_screen
from slopetui.tui.screens.sql import SqlScreen, format_cell
from tests.support import submit_quick

N_RUNS = 5
Scenario = Callable[[Pilot, SlopeApp], Awaitable[None]]


@pytest.fixture(autouse=True)
def history_path(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """Never the user's own history."""
    path = tmp_path / "sql_history"
    monkeypatch.setattr(SqlScreen, "HISTORY_PATH", path)
    return path


@pytest.fixture
def store(db_url: str) -> str:
    """A store with one sweep of N_RUNS queued runs."""
    db = open_store(db_url)
    submit_quick(db, N_RUNS)
    db.dispose()
    return db_url


def dump(db_url: str) -> list[str]:
    conn = sqlite3.connect(db_url.removeprefix("sqlite:///"))
    try:
        return list(conn.iterdump())
    finally:
        conn.close()


def in_console(db_url: str, scenario: Scenario) -> None:
    """Run scenario on the SQL console of an app over db_url, once its store is open."""

    async def main() -> None:
        app = SlopeApp(db_url, start_workers=False)
        async with app.run_test(size=(80, 24)) as pilot:
            await app.workers.wait_for_complete()
            assert app.db is not None
            await app.switch_mode("sql")
            await settle(pilot)
            assert isinstance(app.screen, SqlScreen)
            await scenario(pilot, app)

    asyncio.run(main())


async def settle(pilot: Pilot) -> None:
    """Let the workers finish and their messages arrive."""
    await pilot.app.workers.wait_for_complete()
    await pilot.pause()


async def run_sql(pilot: Pilot, sql: str) -> str:
    """Type sql into the editor, run it with ctrl+r; the status line after it."""
    screen = pilot.app.screen
    screen.query_one("#sql-editor", TextArea).text = sql
    screen.query_one("#sql-editor", TextArea).focus()
    await pilot.press("ctrl+r")
    await settle(pilot)
    return status(pilot)


def status(pilot: Pilot) -> str:
    return str(pilot.app.screen.query_one("#sql-status", Static).render())


def table_rows(pilot: Pilot) -> tuple[list[str], list[list[str]]]:
    table = pilot.app.screen.query_one("#sql-results", DataTable)
    labels = [str(c.label) for c in table.columns.values()]
    rows = [[str(cell) for cell in table.get_row_at(i)] for i in range(table.row_count)]
    return labels, rows


def test_select_fills_the_table(store: str) -> None:
    async def scenario(pilot: Pilot, app: SlopeApp) -> None:
        message = await run_sql(pilot, "SELECT id, k, status, regime FROM runs ORDER BY id")
        assert message.startswith(f"{N_RUNS} rows in"), message
        labels, rows = table_rows(pilot)
        assert labels == ["id", "k", "status", "regime"]
        assert rows == [[str(i + 1), f"{k:g}", "queued", "NULL"]
                        for i, k in enumerate([4, 6, 8, 10, 12])]

        many = ("WITH RECURSIVE c(x) AS (SELECT 1 UNION ALL SELECT x + 1 FROM c "
                "WHERE x < 2500) SELECT x FROM c")
        message = await run_sql(pilot, many)
        assert message.startswith(f"2500 rows (first {sql_screen.DISPLAY_LIMIT} shown)")
        assert app.screen.query_one("#sql-results", DataTable).row_count == \
            sql_screen.DISPLAY_LIMIT

    in_console(store, scenario)


def test_writes_are_refused_and_change_nothing(store: str) -> None:
    before = dump(store)
    writes = ["INSERT INTO workers (id, host, pid) VALUES ('x:1', 'x', 1)",
              "UPDATE runs SET k = 0", "DELETE FROM runs", "DROP TABLE runs",
              "CREATE TABLE t (x)", "PRAGMA query_only = OFF",
              "ATTACH DATABASE 'elsewhere.db' AS other"]

    async def scenario(pilot: Pilot, app: SlopeApp) -> None:
        for sql in writes:
            message = await run_sql(pilot, sql)
            assert message.startswith("refused: the store is opened read-only ("), (sql, message)
        # The console still reads after refusals.
        assert (await run_sql(pilot, "SELECT count(*) FROM runs")).startswith("1 row in")
        assert table_rows(pilot)[1] == [[str(N_RUNS)]]

    in_console(store, scenario)
    assert dump(store) == before


def test_syntax_error_shows_the_database_message(store: str) -> None:
    async def scenario(pilot: Pilot, app: SlopeApp) -> None:
        message = await run_sql(pilot, "SELEC id FROM runs")
        assert message == 'error: near "SELEC": syntax error'
        assert app.screen.query_one("#sql-results", DataTable).row_count == 0

    in_console(store, scenario)


def test_history_records_recalls_and_persists(store: str, history_path: Path) -> None:
    first, second = "SELECT 1 AS one", "SELECT id FROM sweeps"

    async def record(pilot: Pilot, app: SlopeApp) -> None:
        for sql in (first, second, first):  # running first again moves it to the top
            await run_sql(pilot, sql)
        options = app.screen.query_one("#sql-history", OptionList)
        assert options.option_count == 2
        # Recall the older one: focus the list, move down to it, press enter.
        app.screen.query_one("#sql-editor", TextArea).text = ""
        options.focus()
        options.highlighted = 1
        await pilot.press("enter")
        assert app.screen.query_one("#sql-editor", TextArea).text == second
        assert app.screen.focused is app.screen.query_one("#sql-editor")

    in_console(store, record)
    assert read_history(history_path) == [first, second]

    async def reopened(pilot: Pilot, app: SlopeApp) -> None:
        assert app.screen.query_one("#sql-history", OptionList).option_count == 2
        await run_sql(pilot, "SELECT 2")

    in_console(store, reopened)
    assert read_history(history_path) == ["SELECT 2", first, second]


def test_schema_lists_the_tables(store: str) -> None:
    async def scenario(pilot: Pilot, app: SlopeApp) -> None:
        tree = app.screen.query_one("#sql-schema", Tree)
        tables = {str(node.label): node for node in tree.root.children}
        assert {"sweeps", "runs", "workers"} <= tables.keys()
        columns = [str(leaf.label) for leaf in tables["runs"].children]
        assert "id integer pk" in columns and "lambda_max double" in columns
        # The panel toggles; enter on a table types its name into the query.
        await pilot.press("ctrl+b")
        assert not app.screen.query_one("#sql-side").display
        await pilot.press("ctrl+b")
        tree.focus()
        tree.move_cursor(tables["workers"])
        await pilot.press("enter")
        editor = app.screen.query_one("#sql-editor", TextArea)
        assert editor.text.endswith("workers") and app.screen.focused is editor
        await pilot.press("ctrl+l")
        assert editor.text == ""

    in_console(store, scenario)


def test_waits_for_the_database(store: str, monkeypatch: pytest.MonkeyPatch) -> None:
    """Before the app has opened its store the console says so; a query run meanwhile
    runs once the app reports the store open (refresh_data)."""
    monkeypatch.setattr(SlopeApp, "open_store", lambda app: None)

    async def main() -> None:
        app = SlopeApp(store, start_workers=False)
        async with app.run_test(size=(80, 24)) as pilot:
            await app.switch_mode("sql")
            await settle(pilot)
            assert status(pilot) == "opening the database…"
            assert (await run_sql(pilot, "SELECT count(*) AS n FROM runs")) == \
                "opening the database…"
            app.db = open_store(store)
            try:
                app.refresh_active_screen()
                await settle(pilot)
                assert status(pilot).startswith("1 row in")
                assert table_rows(pilot) == (["n"], [[str(N_RUNS)]])
                assert app.screen.query_one("#sql-schema", Tree).root.children
            finally:
                app.db.dispose()

    asyncio.run(main())


# -- the pieces without the UI ---------------------------------------------------------

def test_format_cell() -> None:
    assert str(format_cell(None)) == "NULL"
    assert str(format_cell(1 / 3)) == "0.333333"
    assert str(format_cell(1.5e-12)) == "1.5e-12"
    assert str(format_cell(math.inf)) == "inf"
    assert str(format_cell(42)) == "42"
    assert str(format_cell("[1.0, 2.0]")) == "[1.0, 2.0]"  # not read as markup
    assert str(format_cell("x" * 500)).endswith("…")



# -- time limit and cancellation --------------------------------------------------------

#: About a minute of SQLite on a 2-core box: a broken cancel fails the test, not hangs it.
SLOW = ("WITH RECURSIVE c(x) AS (SELECT 1 UNION ALL SELECT x + 1 FROM c "
        "WHERE x < 300000000) SELECT count(*) FROM c")
RUNNING = "running… (ctrl+g cancels)"


async def start_sql(pilot: Pilot, sql: str) -> None:
    """Type sql and start it; do not wait for it."""
    editor = pilot.app.screen.query_one("#sql-editor", TextArea)
    editor.text = sql
    editor.focus()
    await pilot.press("ctrl+r")
    await pilot.pause()


def test_a_query_times_out(store: str, monkeypatch: pytest.MonkeyPatch) -> None:
    assert SqlScreen.QUERY_TIMEOUT_S == 30
    monkeypatch.setattr(SqlScreen, "QUERY_TIMEOUT_S", 0.5)

    async def scenario(pilot: Pilot, app: SlopeApp) -> None:
        start = time.monotonic()
        message = await run_sql(pilot, SLOW)
        assert time.monotonic() - start < 10
        assert message == "timed out after 0.5 s; nothing shown"
        assert app.screen.query_one("#sql-results", DataTable).row_count == 0
        assert (await run_sql(pilot, "SELECT 1")).startswith("1 row in")

    in_console(store, scenario)


def test_counting_stopped_by_the_limit_keeps_the_rows(store: str,
                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(SqlScreen, "QUERY_TIMEOUT_S", 0.5)
    endless = "WITH RECURSIVE c(x) AS (SELECT 1 UNION ALL SELECT x + 1 FROM c) SELECT x FROM c"

    async def scenario(pilot: Pilot, app: SlopeApp) -> None:
        message = await run_sql(pilot, endless)
        assert message.startswith("at least ") and message.endswith(
            f" rows (first {sql_screen.DISPLAY_LIMIT} shown); counting timed out after "
            "0.5 s"), message
        assert app.screen.query_one("#sql-results", DataTable).row_count == \
            sql_screen.DISPLAY_LIMIT

    in_console(store, scenario)


def test_a_new_query_cancels_the_running_one(store: str,
                                             monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(SqlScreen, "QUERY_TIMEOUT_S", None)  # only a cancel stops it

    async def scenario(pilot: Pilot, app: SlopeApp) -> None:
        await start_sql(pilot, SLOW)
        assert status(pilot) == RUNNING
        first = app.screen._query
        assert first is not None
        start = time.monotonic()
        message = await run_sql(pilot, "SELECT 7 AS seven")  # waits for both workers
        assert time.monotonic() - start < 10
        assert first.cancel_requested
        assert message.startswith("1 row in") and table_rows(pilot) == (["seven"], [["7"]])

    in_console(store, scenario)


def test_ctrl_g_cancels(store: str, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(SqlScreen, "QUERY_TIMEOUT_S", None)

    async def scenario(pilot: Pilot, app: SlopeApp) -> None:
        await start_sql(pilot, SLOW)
        await pilot.press("ctrl+g")
        start = time.monotonic()
        await settle(pilot)
        assert time.monotonic() - start < 10
        assert status(pilot) == "cancelled"
        await pilot.press("ctrl+g")
        assert status(pilot) == "no query is running"

    in_console(store, scenario)


def test_leaving_the_console_cancels(store: str, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(SqlScreen, "QUERY_TIMEOUT_S", None)

    async def scenario(pilot: Pilot, app: SlopeApp) -> None:
        console = app.screen
        await start_sql(pilot, SLOW)
        query = console._query
        await app.switch_mode("sweeps")
        start = time.monotonic()
        await settle(pilot)
        assert time.monotonic() - start < 10
        assert query is not None and query.cancel_requested
        await app.switch_mode("sql")
        await settle(pilot)
        assert status(pilot) == "cancelled"

    in_console(store, scenario)


def test_a_screen_on_top_does_not_cancel(store: str) -> None:
    """The command palette or an error screen over the console is not leaving it."""

    async def scenario(pilot: Pilot, app: SlopeApp) -> None:
        console = app.screen
        await start_sql(pilot, SLOW)
        query = console._query
        await app.push_screen(Screen())
        await pilot.pause()
        assert query is not None and not query.cancel_requested
        app.pop_screen()
        await pilot.pause()
        await pilot.press("ctrl+g")
        await settle(pilot)
        assert status(pilot) == "cancelled"

    in_console(store, scenario)


def test_closing_the_app_cancels(store: str, monkeypatch: pytest.MonkeyPatch,
                                 caplog: pytest.LogCaptureFixture) -> None:
    """Leaving the app waits for its worker threads: the query must stop, not run on;
    and its engine is disposed after the query let go of it, not under it."""
    monkeypatch.setattr(SqlScreen, "QUERY_TIMEOUT_S", None)
    queries = []

    async def scenario(pilot: Pilot, app: SlopeApp) -> None:
        await start_sql(pilot, SLOW)
        queries.append(app.screen._query)

    for _ in range(3):  # the dispose race showed about one time in four
        start = time.monotonic()
        in_console(store, scenario)
        assert time.monotonic() - start < 20
        assert queries[-1].cancel_requested
    assert not [r for r in caplog.records if r.levelno >= logging.WARNING], caplog.text


# -- the history file's permissions (the file itself: tests/unit/test_sql_history.py) -----

def test_the_console_tightens_an_old_history(store: str, history_path: Path) -> None:
    history_path.write_text(json.dumps("SELECT 2") + "\n")
    history_path.chmod(0o644)

    async def scenario(pilot: Pilot, app: SlopeApp) -> None:
        assert app.screen.query_one("#sql-history", OptionList).option_count == 1

    in_console(store, scenario)
    assert stat.S_IMODE(history_path.stat().st_mode) == 0o600


def test_stored_escapes_reach_the_grid_escaped(db_url: str, evil_sweep: int) -> None:
    """`select name, error from sweeps, runs` set the terminal's title and cleared the
    screen: every cell, column name and status line is shown escaped (and never as markup)."""
    hostile = "\x1b]0;owned\x07\x1b[2J\x9b1m\u202eabc [red]x"
    with sqlite3.connect(db_url.removeprefix("sqlite:///")) as conn:
        conn.execute("UPDATE sweeps SET name = ?", (hostile,))
        conn.execute("UPDATE runs SET status = 'failed', error = ? WHERE id = 1", (hostile,))
    conn.close()
    shown = "\\x1b]0;owned\\x07\\x1b[2J\\x9b1m\\u202eabc [red]x"

    async def scenario(pilot: Pilot, app: SlopeApp) -> None:
        message = await run_sql(pilot, f'SELECT name, error AS "{hostile}" FROM sweeps, runs '
                                       "WHERE runs.id = 1")
        assert message.startswith("1 row in"), message
        labels, rows = table_rows(pilot)
        assert labels == ["name", shown] and rows == [[shown, shown]]
        message = await run_sql(pilot, f'SELECT * FROM "{hostile}"')
        assert message == f"error: no such table: {shown}"
        await run_sql(pilot, f'SELECT name, error AS "{hostile}" FROM sweeps, runs')
        # the grid, the status and the history as drawn (the editor shows what was typed)
        app.screen.query_one("#sql-editor", TextArea).text = ""
        await pilot.pause()
        screen = app.export_screenshot()
        assert not any(ch in screen for ch in ("\x1b", "\x07", "\x9b", "\u202e"))

    in_console(db_url, scenario)


def test_ctrl_s_saves_the_rows_shown_and_names_the_file(store: str, tmp_path: Path,
                                                        monkeypatch: pytest.MonkeyPatch) -> None:
    """ctrl+s writes the table's rows, as stored, to a new CSV in the figures' folder (a
    second save takes -2, never replacing the first); the notice names the path and, for
    a result cut at the display limit, how much was saved. Nothing shown: nothing saved."""
    folder = tmp_path / "figures"
    monkeypatch.setenv("SLOPETUI_FIGURES", str(folder))

    def notes(app: SlopeApp) -> list[str]:
        return [n.message for n in app._notifications]

    async def scenario(pilot: Pilot, app: SlopeApp) -> None:
        await pilot.press("ctrl+s")
        await settle(pilot)
        assert notes(app)[-1].startswith("nothing to save") and not folder.exists()
        await run_sql(pilot, "SELECT id, k, char(27) || '[2J' AS raw FROM runs ORDER BY id")
        await pilot.press("ctrl+s")  # the editor has the keys: it does not take ctrl+s
        await settle(pilot)
        assert notes(app)[-1] == f"{N_RUNS} rows saved to {folder / 'sql-results.csv'}"
        assert (folder / "sql-results.csv").read_text().splitlines() == [
            "id,k,raw", *(f"{i + 1},{k:.1f},\x1b[2J" for i, k in enumerate([4, 6, 8, 10, 12]))]
        many = ("WITH RECURSIVE c(x) AS (SELECT 1 UNION ALL SELECT x + 1 FROM c "
                "WHERE x < 2500) SELECT x FROM c")
        await run_sql(pilot, many)
        app.screen.action_save_results("json")  # what the palette's JSON entry calls
        await settle(pilot)
        shown = sql_screen.DISPLAY_LIMIT
        assert notes(app)[-1].startswith(f"{shown} rows saved to {folder / 'sql-results.json'} "
                                         f"(the first {shown} of 2500, as shown;")
        assert json.loads((folder / "sql-results.json").read_text())[-1] == {"x": shown}
        await pilot.press("ctrl+s")
        await settle(pilot)
        assert (folder / "sql-results-2.csv").is_file()
        assert (folder / "sql-results.csv").read_text().startswith("id,k,raw\n")

    in_console(store, scenario)


def test_two_saves_at_once_take_two_names(store: str, tmp_path: Path,
                                          monkeypatch: pytest.MonkeyPatch) -> None:
    """A second ctrl+s while the first is still writing (a long result) takes its own
    name: the first file, finished after the second, does not replace it."""
    folder = tmp_path / "figures"
    monkeypatch.setenv("SLOPETUI_FIGURES", str(folder))
    writing, release = threading.Event(), threading.Event()

    class HeldRows(list):  # the first save's rows: held while they are written
        def __iter__(self) -> Iterator[tuple[object, ...]]:
            writing.set()
            release.wait(10)
            return super().__iter__()

    async def scenario(pilot: Pilot, app: SlopeApp) -> None:
        screen = app.screen
        assert isinstance(screen, SqlScreen)
        screen.results = QueryDone(["who"], HeldRows([("first",)]), 1, 0.0)
        screen.action_save_results()
        assert await asyncio.to_thread(writing.wait, 10)
        screen.results = QueryDone(["who"], [("second",)], 1, 0.0)
        screen.action_save_results()
        for _ in range(200):  # the second save ends while the first is still writing
            if (folder / "sql-results.csv").exists():
                break
            await asyncio.sleep(0.05)
        release.set()
        await settle(pilot)
        saved = {p.name: p.read_text() for p in folder.iterdir()}
        assert saved == {"sql-results.csv": "who\nsecond\n", "sql-results-2.csv": "who\nfirst\n"}

    in_console(store, scenario)
