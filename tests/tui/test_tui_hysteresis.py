"""Pilot tests of the hysteresis sweeps on the branches screen (key 4): listed in their own
table below the continuations, the highlighted one drawn as one diagram of both branches,
with where each branch changes regime, or its progress."""

from __future__ import annotations

import math

import numpy as np

from core.params import Params
from slopetui.queue.hysteresis_jobs import HysteresisSpec
from slopetui.store.database import Database
from slopetui.store.jobs import hysteresis_sweeps
from slopetui.sweeps.hysteresis_runs import submit
from slopetui.tui.screens.branches import BranchesScreen
from slopetui.tui.widgets.plot_view import PlotView
from tests.tui.support import run, wait_until
from tests.tui.test_tui_branches import app_for, cells, continuation

SPEC = HysteresisSpec(Params(tau=10.0), "k", 0.5, 8.0, 3, 0.01, 6000.0, 1000.0)
#: (direction, k, regime, amplitude, growth, jumped): up rests, then jumps to the cycle;
#: down keeps the cycle down to k = 4.25 and rests at 0.5.
SHAPE = [("up", 0.5, "sliding", 1e-6, -0.01, False), ("up", 4.25, "sliding", 1e-6, -0.001, False),
         ("up", 8.0, "oscillatory", 2.5, 0.002, True),
         ("down", 8.0, "oscillatory", 2.5, math.nan, False),
         ("down", 4.25, "oscillatory", 1.9, math.nan, False),
         ("down", 0.5, "sliding", 1e-6, -0.01, False)]


def sweep(db: Database, n: int = len(SHAPE), *, finish: bool = True) -> int:
    """A hysteresis sweep with its first ``n`` points saved and, if asked, finished."""
    sid = submit(db, SPEC)
    assert hysteresis_sweeps.claim(db, "w1") is not None
    for i, (direction, k, regime, amplitude, growth, jumped) in enumerate(SHAPE[:n]):
        assert hysteresis_sweeps.save_point(db, sid, "w1", {
            "idx": i, "direction": direction, "value": k, "regime": regime, "detail": "",
            "amplitude": amplitude, "growth": growth, "jumped": jumped,
            "state": np.zeros(3).tobytes()}, 0.1)
    if finish:
        assert hysteresis_sweeps.finish(db, sid, "w1", {
            "onset_up": 6.1431, "onset_up_before": 4.25, "onset_up_after": 8.0,
            "offset_down": 1.2144, "offset_down_before": 4.25, "offset_down_after": 0.5}, 0.0)
    return sid


async def _open(pilot, app):
    await wait_until(pilot, lambda: app.db is not None)
    await pilot.press("4")
    await wait_until(pilot, lambda: isinstance(app.screen, BranchesScreen))


def test_a_finished_sweep_is_listed_and_drawn_with_its_changes(db):
    sid = sweep(db)

    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            await _open(pilot, app)
            table = app.screen.query_one("#hyst-table")
            await wait_until(pilot, lambda: table.row_count == 1)
            assert cells(table, 0) == [str(sid), "k", "0.5→8 τ=10", "done", "6/6", "6.1431",
                                       "1.2144"]
            assert not app.screen.query_one("#branch-table").display  # no continuations
            plot = app.screen.query_one(PlotView)
            await wait_until(pilot, lambda: "m_y amplitude" in str(plot.render()))
            drawn = str(plot.render())
            assert f"hysteresis {sid} in k" in drawn and "up 3" in drawn and "down 3" in drawn
            detail = str(app.screen.query_one("#branch-detail").render())
            assert ("up leaves rest at k = 6.1431 [4.25, 8], down leaves the cycle at "
                    "k = 1.2144 [4.25, 0.5]") in detail

    run(scenario)


def test_tab_moves_between_continuations_and_sweeps_and_a_running_one_grows(db):
    continuation(db)
    sid = sweep(db, 2, finish=False)

    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            await _open(pilot, app)
            screen = app.screen
            table = screen.query_one("#hyst-table")
            detail = screen.query_one("#branch-detail")
            plot = screen.query_one(PlotView)
            await wait_until(pilot, lambda: table.row_count == 1
                             and "fold k = 1.2139" in str(detail.render()))
            assert screen.query_one("#branch-table").display and table.display
            assert plot.size.height >= 12  # both tables at 80x24 leave the plot its minimum
            await pilot.press("tab")  # into the sweeps' table: its row is drawn
            await wait_until(pilot, lambda: "running: 2 of 6 points so far"
                             in str(detail.render()))
            await wait_until(pilot, lambda: f"hysteresis {sid}" in str(plot.render()))
            assert "up 2" in str(plot.render())
            # a worker elsewhere saves the next point: the periodic refresh shows it
            assert hysteresis_sweeps.save_point(db, sid, "w1", {
                "idx": 2, "direction": "up", "value": 8.0, "regime": "oscillatory",
                "detail": "", "amplitude": 2.5, "growth": 0.002, "jumped": True,
                "state": b""}, 0.1)
            await wait_until(pilot, lambda: cells(table, 0)[4] == "3/6"
                             and "up 3" in str(plot.render()))
            await pilot.press("shift+tab")  # back to the continuation
            await wait_until(pilot, lambda: "fold k = 1.2139" in str(detail.render()))

    run(scenario)
