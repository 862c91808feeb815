"""The keys of the sweeps screen act on the sweep the user sees as selected: the row
the list highlights, whose diagram is the one on show.

Twice x offered to delete a sweep the user had not meant, and after d or a click in the
diagram the arrows moved over the diagram of the sweep selected before: the diagram of
the old sweep stayed on show (and took the focus) while the new one's was read, and a
refresh landing between a key and its highlight put the list's cursor back on the old
row while the new sweep was selected. A slow read is made here by holding the new
sweep's read until the test lets it go.
"""

from __future__ import annotations

import threading
from dataclasses import replace

from textual.widgets import DataTable

from slopetui.sweeps.live_diagram import LiveDiagram
from slopetui.tui.app import SlopeApp
from slopetui.tui.screens import sweeps as sweeps_screen
from slopetui.tui.screens.confirm import ConfirmScreen
from slopetui.tui.screens.sweeps import SweepsScreen
from slopetui.tui.widgets.bifurcation_view import BifurcationView
from slopetui.tui.widgets.phase_grid import LABEL_WIDTH, PhaseGrid
from tests.support import finish_all, submit_quick
from tests.tui.support import run, wait_until
from tests.tui.test_tui_app import app_for, plane


def highlighted(screen: SweepsScreen) -> int:
    """The sweep of the row the list's cursor is on."""
    table = screen.query_one("#sweep-table", DataTable)
    key = table.coordinate_to_cell_key(table.cursor_coordinate).row_key.value
    assert key is not None
    return int(key)


def question(app: SlopeApp) -> str:
    return str(app.screen.query_one("#confirm-question").render())


def held_reads(monkeypatch, sweep_id: int) -> threading.Event:
    """Hold every read of ``sweep_id``'s diagram until the returned event is set (a large
    sweep on a loaded machine: seconds)."""
    release = threading.Event()

    class Slow(LiveDiagram):
        def refresh(self, db):
            if self.sweep_id == sweep_id:
                release.wait(30)
            return super().refresh(db)

    monkeypatch.setattr(sweeps_screen, "LiveDiagram", Slow)
    return release


def two_sweeps(db) -> tuple[int, int]:
    """A 1-D sweep, then a (k, tau) plane listed above it and selected first."""
    line = submit_quick(db, 3).sweep_id
    grid = plane(db)
    finish_all(db)
    return grid, line


def test_d_a_click_arrows_and_x_act_on_the_highlighted_sweep_while_its_diagram_is_read(
        db, monkeypatch):
    grid_sweep, line_sweep = two_sweeps(db)
    release = held_reads(monkeypatch, line_sweep)

    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            screen = app.screen
            assert isinstance(screen, SweepsScreen)
            phase_grid = screen.query_one(PhaseGrid)
            await wait_until(pilot, lambda: phase_grid.data is not None
                             and screen.selected == grid_sweep)
            await pilot.press("down")  # the 1-D sweep: its read is held
            assert highlighted(screen) == line_sweep
            await pilot.press("d")
            # the plane's diagram is not the one on show, and has not taken the keys
            assert not phase_grid.display or not phase_grid.has_focus
            assert not isinstance(app.focused, PhaseGrid)
            await pilot.click("#diagram-pane", offset=(20, 4))
            assert not isinstance(app.focused, PhaseGrid)
            cursor = phase_grid.cursor
            await pilot.press("left", "right", "up", "down")  # the list has the keys
            assert phase_grid.cursor == cursor  # the plane's cursor did not move
            assert highlighted(screen) == line_sweep
            await pilot.press("x")
            await wait_until(pilot, lambda: isinstance(app.screen, ConfirmScreen))
            assert f"Delete sweep {line_sweep} " in question(app)
            await pilot.press("escape")
            await wait_until(pilot, lambda: app.screen is screen)
            release.set()  # the 1-D sweep's diagram arrives: d moves into it
            await wait_until(pilot, lambda: screen.query_one("#diagram-switcher").current
                             == "bifurcation")
            view = screen.query_one(BifurcationView)
            resting = view.background_colors[1]
            await pilot.press("d")
            assert isinstance(app.focused, BifurcationView)
            await pilot.pause()
            assert view.background_colors[1] != resting  # lit: it has the keys now
            await pilot.press("x")
            await wait_until(pilot, lambda: isinstance(app.screen, ConfirmScreen))
            assert f"Delete sweep {line_sweep} " in question(app)
            await pilot.press("escape")

    try:
        run(scenario)
    finally:
        release.set()


def test_a_refresh_between_a_key_and_its_highlight_keeps_the_users_row(db, monkeypatch):
    grid_sweep, line_sweep = two_sweeps(db)
    release = held_reads(monkeypatch, line_sweep)  # nothing corrects the list meanwhile

    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            screen = app.screen
            assert isinstance(screen, SweepsScreen)
            await wait_until(pilot, lambda: screen.query_one(PhaseGrid).data is not None
                             and screen.selected == grid_sweep)
            table = screen.query_one("#sweep-table", DataTable)
            # The cursor moves (its highlight is posted, not yet handled), and a refresh
            # read before the key lands first: its rows differ (a rate changed).
            table.action_cursor_down()
            newer = [replace(p, runs_per_min=p.runs_per_min + 1) for p in screen._sweeps]
            screen.on_sweeps_screen_loaded(SweepsScreen.Loaded(newer, screen._shown,
                                                               screen._shown_grid))
            await pilot.pause()
            assert screen.selected == line_sweep
            assert highlighted(screen) == line_sweep  # the key the user pressed holds
            await pilot.press("x")
            await wait_until(pilot, lambda: isinstance(app.screen, ConfirmScreen))
            assert f"Delete sweep {line_sweep} " in question(app)
            await pilot.press("escape")
            release.set()  # before the app exits: it waits for the held read

    try:
        run(scenario)
    finally:
        release.set()


def test_a_click_in_the_phase_diagram_puts_the_cursor_on_the_run_clicked(db):
    grid_sweep, _ = two_sweeps(db)

    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            screen = app.screen
            assert isinstance(screen, SweepsScreen)
            phase_grid = screen.query_one(PhaseGrid)
            await wait_until(pilot, lambda: phase_grid.data is not None
                             and screen.selected == grid_sweep)
            view = phase_grid.view()
            assert view is not None and not view.half and (view.sx, view.sy) == (1, 1)
            col, row = 4, 1  # a run away from the cursor's first place (0, 0)
            text_row = view.row0 + view.view_rows - 1 - row
            await pilot.click(PhaseGrid, offset=(LABEL_WIDTH + col * view.cell_w, text_row))
            assert phase_grid.has_focus and phase_grid.cursor == (col, row)
            found = phase_grid.cursor_run()
            assert found is not None
            run_id, x, y, _ = found
            assert (x, y) == (float(phase_grid.data.xs[col]), float(phase_grid.data.ys[row]))
            await pilot.press("enter")  # opens the run clicked
            await wait_until(pilot, lambda: getattr(app.screen, "run_id", None) == run_id)

    run(scenario)
