"""Complete at 80 x 24: the essential text of every screen is on the
screen as drawn, whole, at 80 x 24 and at 120 x 40.

Cut off before: the run detail's result lines after the first (attractor, settled,
flags, and the fields added since: certified, certificate, multipliers, slips, dt
error), the λmax note (ending in "…"), the form's δ-list placeholder, and the queue's
"since" column when no worker was live. The run detail's Roots tab (the rest state's
verdict, every root listed, their plot with its legend) is checked whole too.
"""

from __future__ import annotations

import pytest

from core.result_fields import DETAIL_FIELDS
from slopetui.sweeps.recompute import MATCH_TEXT, load_run
from slopetui.tui.app import SlopeApp
from slopetui.tui.screens.branches import BranchesScreen
from slopetui.tui.screens.compare import CompareScreen
from slopetui.tui.screens.help import HelpScreen
from slopetui.tui.screens.new_sweep import NewSweepScreen
from slopetui.tui.screens.queue import QueueScreen
from slopetui.tui.screens.run_detail import RECOMPUTED_NOTE, RunDetailScreen, result_item
from slopetui.tui.screens.sql import SqlScreen
from slopetui.tui.screens.sweeps import COLUMNS, SweepsScreen
from slopetui.tui.widgets.phase_grid import PhaseGrid
from slopetui.tui.widgets.roots_view import roots_lines
from tests.support import finish_all, submit_quick
from tests.tui.support import open_form, run, wait_until
from tests.tui.test_tui_app import app_for, plane
from tests.tui.test_tui_keyboard import screen_lines

SIZES = [(80, 24), (120, 40)]


def drawn(app: SlopeApp) -> str:
    """The screen as drawn, whitespace collapsed: a text wrapped over lines reads whole."""
    return " ".join(" ".join(screen_lines(app)).split())


class Missing(list):
    """What a screen did not show whole, over every screen visited (all are listed when
    the test fails, not the first only)."""

    def check(self, app: SlopeApp, *texts: str) -> None:
        """Each text is on the screen, whole (wrapped, perhaps), and no line is cut."""
        shown = drawn(app)
        name = type(app.screen).__name__
        self.extend(f"{name}: {text!r}" for text in texts
                    if " ".join(text.split()) not in shown)
        self.extend(f"{name}: cut {line.strip()!r}" for line in screen_lines(app)
                    if line.rstrip().endswith("…"))


@pytest.mark.parametrize("size", SIZES)
def test_every_screen_shows_its_essential_text_whole(db, size):
    line_sweep = submit_quick(db, 2, t_end=600.0).sweep_id  # k = 4 at rest, k = 12 cycling
    plane(db)
    finish_all(db)
    resting, cycling = (load_run(db, i) for i in (1, 2))
    assert resting is not None and cycling is not None
    assert resting.sweep_id == line_sweep and cycling.attractor == "periodic"

    missing = Missing()

    async def scenario():
        app = app_for(db)
        async with app.run_test(size=size) as pilot:
            # sweeps: the list's columns, the diagram, its legend and its cursor's line
            grid = app.query_one(PhaseGrid)
            await wait_until(pilot, lambda: grid.data is not None
                             and None not in {r for _, r in grid.data.runs.values()})
            await pilot.pause()
            missing.check(app, " ".join(COLUMNS), "tau ↑", "→ k",
                         "sliding (", "Hopf (exact)", "enter opens it", "? Help", "^q Quit")

            # the run detail: every stored result field, the status, the tabs, the note
            for stored in (cycling, resting):
                app.open_run(stored.id)
                await pilot.pause()
                detail = app.screen
                assert isinstance(detail, RunDetailScreen)
                await wait_until(pilot, lambda d=detail: d.traces is not None, 120)
                await pilot.pause()
                items = [result_item(stored, f) for f in DETAIL_FIELDS]
                assert len(items) >= 16  # certified ... dt error included
                missing.check(app, f"run {stored.id} · sweep {stored.sweep_id}",
                             f"k {stored.k:g}", f"engine {stored.engine}", *items,
                             MATCH_TEXT, RECOMPUTED_NOTE, "Time series", "Phase portrait",
                             "Spectrum", "λmax", "esc Back", "^q Quit")
                await pilot.press("l")  # the λmax note: which map, and its bias, whole
                await pilot.pause(0.3)
                assert detail.traces is not None and detail.traces.lambda_note
                missing.check(app, detail.traces.lambda_note, "running λ(t)")
                await pilot.press("e")  # the rest state's roots: verdict, list and plot
                await wait_until(pilot, lambda d=detail: d.roots is not None, 60)
                await pilot.pause(0.3)
                assert detail.roots is not None
                missing.check(app, "Roots", *roots_lines(detail.roots), "Re λ", "Im λ",
                             "Re = 0", "variance block")
                await pilot.press("escape")
                await wait_until(pilot, lambda: isinstance(app.screen, SweepsScreen))

            # the form: every label, the δ list's placeholder, the estimate, the keys
            await open_form(app, pilot)
            await pilot.pause()
            missing.check(app, "preset:", "name:", "adaptive levels", "parameter", "start",
                         "stop", "points", "spacing", "x:", "y:", "fixed:", "delta",
                         "solver:", "dt", "t_end", "window", "λmax", "start:", "δ list",
                         "e.g. 1e-6, 0.1: a map of where they differ", "≈ 228 runs",
                         "^s Submit", "tab Next field", "esc Cancel")
            assert isinstance(app.screen, NewSweepScreen)
            await pilot.press("escape")
            await wait_until(pilot, lambda: isinstance(app.screen, SweepsScreen))

            # the queue: both tables' columns, and how to start workers
            await pilot.press("2")
            await wait_until(pilot, lambda: isinstance(app.screen, QueueScreen)
                             and "k 4..12" in drawn(app))
            missing.check(app, "none live (slopetui worker --detach starts them)",
                         "worker running jobs done heartbeat since",
                         "id status queued running done failed cancelled name", "k 4..12",
                         "p Pause", "c Cancel")

            # the SQL console: the editor and how to leave it, the status, the panels
            await pilot.press("3")
            await wait_until(pilot, lambda: isinstance(app.screen, SqlScreen))
            await pilot.pause()
            missing.check(app, "query", "typing here · esc or tab leaves",
                         "ctrl+r runs the query", "schema", "history", "^r Run",
                         "esc/tab Leave editor")
            await pilot.press("tab")  # out of the editor: 4 switches screens

            # the branches: what there is, and how to queue one
            await pilot.press("4")
            await wait_until(pilot, lambda: isinstance(app.screen, BranchesScreen)
                             and "No continuations yet" in drawn(app))
            missing.check(app, "c queues one", "h a hysteresis sweep", "point by point",
                         "c New continuation", "h New hysteresis")

            # the analysis forms: every field, the estimate, how to start and leave
            await pilot.press("c")
            await wait_until(pilot, lambda: "≈ from the Hopf point" in drawn(app))
            missing.check(app, "param k", "from hopf", "to (none)", "points 300", "tau 10",
                         "delta 0.1", "dt 0.01", "max-step 0.5", "at most 300 points",
                         "Queue (ctrl+s)", "^s Start", "esc Cancel")
            await pilot.press("escape")
            await pilot.press("h")
            await wait_until(pilot, lambda: "≈ 42 points (up and down)" in drawn(app))
            missing.check(app, "param k", "from 8", "to 12", "points 21", "t-settle 6000",
                         "window 1000", "tol 0.001", "Queue (ctrl+s)")
            await pilot.press("escape")
            await wait_until(pilot, lambda: isinstance(app.screen, BranchesScreen))
            app.open_analysis("orbit")
            await wait_until(pilot, lambda: "≈ a seed simulation" in drawn(app))
            missing.check(app, "Periodic orbit at a point", "dt 0.01", "t-seed 3000",
                         "Compute (ctrl+s)", "^s Start")
            await pilot.press("escape")
            app.certified_rerun(cycling.id)
            await wait_until(pilot, lambda: "it stops where its attractor is certified"
                             in drawn(app))
            missing.check(app, "Certified re-run of a run", f"run {cycling.id}",
                         "Queue (ctrl+s)", "esc Cancel")
            await pilot.press("escape")
            await wait_until(pilot, lambda: isinstance(app.screen, BranchesScreen))

            # the comparison of two runs, and the help
            await pilot.press("1")
            await wait_until(pilot, lambda: isinstance(app.screen, SweepsScreen))
            app.marked[:] = [resting.id, cycling.id]
            await pilot.press("v")
            await wait_until(pilot, lambda: isinstance(app.screen, CompareScreen)
                             and "recomputed" in drawn(app), 120)
            missing.check(app, f"comparing runs {resting.id}, {cycling.id}",
                         f"run {resting.id}: k 4", f"run {cycling.id}: k 12", "f Figure")
            await pilot.press("escape")
            await pilot.press("question_mark")
            await wait_until(pilot, lambda: isinstance(app.screen, HelpScreen))
            await pilot.pause()
            missing.check(app, "Keys: Sweeps", "This screen (Sweeps)", "esc, q or ? closes")

    run(scenario)
    assert not missing, "\n".join(missing)
