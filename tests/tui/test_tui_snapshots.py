"""Snapshots of the main screens at 80x24 and at a large size (pytest-textual-snapshot).

Update them after a deliberate change with ``pytest tests/tui/test_tui_snapshots.py
--snapshot-update`` and review the SVGs in tests/tui/__snapshots__/test_tui_snapshots/.
"""

from __future__ import annotations

import pytest
from textual.widgets import TextArea

from slopetui.sweeps.spec import parse_spec
from slopetui.sweeps.submit import submit
from slopetui.tui.app import SlopeApp
from slopetui.tui.screens import sql as sql_screen
from slopetui.tui.screens.sql import SqlScreen
from slopetui.tui.widgets.phase_grid import PhaseGrid
from tests.support import QUICK_SOLVER, finish_all
from tests.tui.support import wait_until

SIZES = [(80, 24), (140, 44)]


@pytest.fixture
def finished_plane(db):
    spec = parse_spec({"name": "(k, tau) plane", "x": {"param": "k", "start": 2, "stop": 20,
                                                       "num": 10},
                       "y": {"param": "tau", "start": 0.5, "stop": 10, "num": 8},
                       "solver": QUICK_SOLVER})
    submit(db, spec)
    finish_all(db)
    # A finished sweep's runs per minute are over its life, first start to last finish:
    # date them, so the snapshot does not depend on how long they took (80 runs in 1 s).
    with db.engine.begin() as conn:
        conn.exec_driver_sql("UPDATE runs SET started_at = '2000-01-01 00:00:00', "
                             "finished_at = '2000-01-01 00:00:01'")
    return db


def app_for(db) -> SlopeApp:
    return SlopeApp(db.display_url, start_workers=False, refresh_s=60)


async def grid_loaded(pilot) -> None:
    grid = pilot.app.query_one(PhaseGrid)
    await wait_until(pilot, lambda: grid.data is not None)
    await pilot.press("d", "right", "right", "up")
    await pilot.pause()


@pytest.mark.parametrize("size", SIZES)
def test_sweeps_screen(snap_compare, finished_plane, size):
    assert snap_compare(app_for(finished_plane), terminal_size=size, run_before=grid_loaded)


@pytest.mark.parametrize("size", SIZES)
def test_new_sweep_screen(snap_compare, finished_plane, size):
    async def open_form(pilot) -> None:
        await wait_until(pilot, lambda: pilot.app.db is not None)
        await pilot.press("n")
        await pilot.pause()
        for widget in pilot.app.screen.query("Input"):
            widget.cursor_blink = False
        await pilot.pause()

    assert snap_compare(app_for(finished_plane), terminal_size=size, run_before=open_form)


def test_sql_screen(snap_compare, finished_plane, tmp_path, monkeypatch):
    monkeypatch.setattr(SqlScreen, "HISTORY_PATH", tmp_path / "history")
    # the status line reports the query's time, which differs from run to run
    monkeypatch.setattr(sql_screen, "duration_text", lambda seconds, fine: "(time)")
    # the editor stays plain text: with tree-sitter's SQL grammar installed (textual[syntax])
    # the console would highlight the query, and the snapshot would depend on the machine
    monkeypatch.setattr(TextArea, "validate_language", lambda self, language: None,
                        raising=False)

    async def query(pilot) -> None:
        await wait_until(pilot, lambda: pilot.app.db is not None)
        await pilot.press("3")
        await pilot.pause()
        await pilot.press("ctrl+r")
        table = pilot.app.screen.query_one("DataTable")
        await wait_until(pilot, lambda: table.row_count > 0)
        editor = pilot.app.screen.query_one("TextArea")
        editor.cursor_blink = False
        # the snapshot shows the focused editor's cursor: under load, wait for the focus
        await wait_until(pilot, lambda: editor.has_focus)
        await pilot.pause()

    assert snap_compare(app_for(finished_plane), terminal_size=(80, 24), run_before=query)
