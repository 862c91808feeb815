"""Pilot tests of the branches screen (key 4: stored continuations and the highlighted
one's diagram) and of the fold of cycles over a (k, tau) phase diagram (key o)."""

from __future__ import annotations

import threading

import numpy as np
from textual.widgets import DataTable

from core.branch_start import BranchSpec
from core.params import Params
from slopetui.queue.branch_jobs import fields_of
from slopetui.store.database import Database
from slopetui.store.jobs import continuations
from slopetui.sweeps import fold_overlay
from slopetui.sweeps.spec import parse_spec
from slopetui.sweeps.submit import submit
from slopetui.tui.app import SlopeApp
from slopetui.tui.screens import branches as branches_screen
from slopetui.tui.screens.branches import BranchesScreen
from slopetui.tui.widgets.bifurcation_view import BifurcationView
from slopetui.tui.widgets.phase_grid import PhaseGrid
from slopetui.tui.widgets.plot_view import PlotView
from tests.support import QUICK_SOLVER, submit_quick
from tests.tui.support import run, wait_until

FOLD_K = 1.2139


async def branch_table(pilot, app: SlopeApp) -> DataTable:
    """The continuations table of the branches screen, once key 4 has shown it."""
    await wait_until(pilot, lambda: app.db is not None)
    await pilot.press("4")
    await wait_until(pilot, lambda: isinstance(app.screen, BranchesScreen))
    return app.screen.query_one("#branch-table", DataTable)


def point(idx: int, value: float, amplitude: float, stable: bool) -> dict:
    return {"idx": idx, "value": value, "period": 25.0 + idx, "amplitude": amplitude,
            "stable": stable, "unstable_count": 0 if stable else 1, "leading_re": 0.9,
            "leading_im": 0.0, "multipliers": [[0.9, 0.0]], "flow_index": 0,
            "translation": 0.0, "step": 0.1, "state": b"\0" * 16}


def continuation(db: Database, *, finish: bool = True) -> int:
    """A continuation in k from the Hopf point, with five points (two unstable, three
    stable) and, once finished, a fold of cycles."""
    cid = continuations.submit(db, fields_of(BranchSpec(params=Params(), name="k", dt=0.01,
                                                      from_hopf=True)))
    assert continuations.claim(db, "w1") is not None
    shape = [(1.30, 0.2, False), (1.22, 0.6, False), (1.23, 1.0, True), (1.30, 1.4, True),
             (1.40, 1.8, True)]
    for i, (k, amplitude, stable) in enumerate(shape):
        assert continuations.save_point(db, cid, "w1", point(i, k, amplitude, stable), 0.0,
                                      hopf=(1.35, 24.0) if i == 0 else None)
    if finish:
        assert continuations.finish(db, cid, "w1", "reached the requested end", "subcritical",
                                  1.0, [{"type": "fold", "value": FOLD_K, "period": 30.0,
                                         "mu_re": 1.0, "mu_im": 0.0}])
    return cid


def app_for(db: Database) -> SlopeApp:
    return SlopeApp(db.display_url, start_workers=False, refresh_s=0.2)


def cells(table, row: int) -> list[str]:
    return [str(c) for c in table.get_row_at(row)]


def test_the_branches_screen_lists_and_draws_a_finished_continuation(db):
    cid = continuation(db)

    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            table = await branch_table(pilot, app)
            await wait_until(pilot, lambda: table.row_count == 1)
            row = cells(table, 0)
            assert row[0] == str(cid) and row[1] == "k" and row[3] == "done"
            assert row[2].startswith("hopf1 k=1.35") and row[4] == "5"
            assert row[5] == "subcritical" and row[6] == f"fold k={FOLD_K}"
            plot = app.screen.query_one(PlotView)
            await wait_until(pilot, lambda: "m_y amplitude" in str(plot.render()))
            drawn = str(plot.render())
            assert f"continuation {cid} in k" in drawn and "fold 1" in drawn
            assert "stable 3" in drawn and "unstable 2" in drawn
            detail = str(app.screen.query_one("#branch-detail").render())
            assert f"fold k = {FOLD_K}" in detail and "period 30" in detail
            assert "end: reached the requested end" in detail
            assert "; subcritical Hopf point 1" in detail  # which one it started at

    run(scenario)


def test_a_running_continuation_grows_as_its_points_are_saved(db):
    cid = continuation(db, finish=False)

    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            table = await branch_table(pilot, app)
            await wait_until(pilot, lambda: table.row_count == 1
                             and cells(table, 0)[3] == "running")
            detail = app.screen.query_one("#branch-detail")
            await wait_until(pilot, lambda: "5 points so far" in str(detail.render()))
            # a worker elsewhere saves the next point: the periodic refresh shows it
            assert continuations.save_point(db, cid, "w1", point(5, 1.5, 2.2, True), 0.0)
            await wait_until(pilot, lambda: cells(table, 0)[4] == "6"
                             and "6 points so far" in str(detail.render()))
            plot = app.screen.query_one(PlotView)
            await wait_until(pilot, lambda: "stable 4" in str(plot.render()))

    run(scenario)


def test_an_idle_branches_screen_reads_nothing_with_a_row_below_the_first_selected(
        db, monkeypatch):
    """Each refill of the table announced its first row as highlighted: with any other
    continuation selected, that one and then the selected one were loaded again, each
    load refilling the table, a whole core on an idle screen (BranchesScreen._fill_table)."""
    older, newer = continuation(db), continuation(db)
    reads: list[int] = []
    real = branches_screen.listing

    def counted(*args, **kwargs):
        reads.append(1)
        return real(*args, **kwargs)

    monkeypatch.setattr(branches_screen, "listing", counted)

    async def scenario():
        app = SlopeApp(db.display_url, start_workers=False, refresh_s=60.0)
        async with app.run_test(size=(80, 24)) as pilot:
            table = await branch_table(pilot, app)
            await wait_until(pilot, lambda: table.row_count == 2)
            assert app.screen.selected == ("branch", newer)  # the first row
            await pilot.press("down")
            await pilot.pause(0.5)  # the second continuation is read and drawn
            before = len(reads)
            await pilot.pause(1.0)  # idle: the next refresh is a minute away
            assert len(reads) - before <= 1, f"{len(reads) - before} reads in an idle second"
            assert app.screen.selected == ("branch", older) and table.cursor_row == 1

    run(scenario)


def test_no_continuations_says_how_to_queue_one(db):
    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            await wait_until(pilot, lambda: app.db is not None)
            await pilot.press("4")
            await wait_until(pilot, lambda: isinstance(app.screen, BranchesScreen))
            detail = app.screen.query_one("#branch-detail")
            # the keys that open the forms, not a command line to type elsewhere
            await wait_until(pilot, lambda: "c queues one" in str(detail.render()))
            assert "h a hysteresis sweep" in str(detail.render())

    run(scenario)


def said_by(app: SlopeApp) -> list[str]:
    said: list[str] = []
    notify = app.notify
    app.notify = lambda message, **kw: (said.append(message), notify(message, **kw))[1]
    return said


def test_the_fold_curve_is_for_x_tau_planes_only(db):
    submit_quick(db, 3)  # a 1-D sweep

    async def scenario():
        app = app_for(db)
        said = said_by(app)
        async with app.run_test(size=(80, 24)) as pilot:
            view = app.query_one(BifurcationView)
            await wait_until(pilot, lambda: view.diagram is not None)
            await pilot.press("o")
            await wait_until(pilot, lambda: any("(x, tau) phase diagrams only" in s
                                                for s in said))
            assert app.fold_curves == {}

    run(scenario)


def test_the_fold_curve_is_computed_once_and_drawn(db, monkeypatch):
    spec = parse_spec({"x": {"param": "k", "start": 0.5, "stop": 3, "num": 6},
                       "y": {"param": "tau", "start": 1, "stop": 4, "num": 3},
                       "solver": QUICK_SOLVER})
    sweep = submit(db, spec).sweep_id
    release = threading.Event()
    calls: list[int] = []

    def fake_fold_overlay(spec, progress):  # the real one takes seconds per tau
        calls.append(1)
        taus = spec.y.values()
        for tau in taus:
            progress(float(tau), 1.0 + 0.1 * float(tau))
            release.wait(10)
        return np.array([1.0 + 0.1 * t for t in taus]), np.array(taus, dtype=float)

    monkeypatch.setattr(fold_overlay, "fold_overlay", fake_fold_overlay)

    async def scenario():
        app = app_for(db)
        said = said_by(app)
        async with app.run_test(size=(80, 24)) as pilot:
            grid = app.query_one(PhaseGrid)
            await wait_until(pilot, lambda: grid.data is not None)
            await pilot.press("o")
            await wait_until(pilot, lambda: "fold of cycles: tau 1/3" in str(app.screen.sub_title))
            await pilot.press("o")  # a second press while computing only says so
            await wait_until(pilot, lambda: any("still computing" in s for s in said))
            release.set()
            await wait_until(pilot, lambda: sweep in app.fold_curves
                             and grid.data.fold is not None)
            assert "• fold" in str(grid.render())  # the legend; the cells carry a • too
            assert app.screen.sub_title is None
            await pilot.press("o")  # cached for the session: not computed again
            await wait_until(pilot, lambda: any("is drawn" in s for s in said))
            assert len(calls) == 1

    run(scenario)


def stored_curve(db: Database) -> int:
    """A fold curve in (k, tau) with four points, finished with a Bautin point."""
    from core.curve_start import CurveSpec
    from slopetui.queue.curve_jobs import submit as submit_curve
    from slopetui.store.jobs import curves
    from tests.unit.test_curve_jobs import _point as curve_point

    cid = submit_curve(db, CurveSpec(Params(tau=2.0), "k", "tau", "fold", 0.01, 0.5, 50, 0.5))
    assert curves.claim(db, "w1") is not None
    for i in range(4):
        assert curves.save_point(db, cid, "w1", curve_point(i), 0.0)
    assert curves.finish(db, cid, "w1", "the amplitude vanished", 1.0, [
        {"type": "bautin", "first": 26.2247, "second": 0.64995, "period": 0.987,
         "note": "the fold curve's end on the Hopf curve"}])
    return cid


def test_all_three_kinds_show_at_80x24_and_a_curve_is_drawn_in_its_plane(db):
    """With a continuation, a hysteresis sweep and a curve stored, each table keeps its
    header and a row at 80 x 24, and the highlighted curve is drawn in (k, tau) with its
    Bautin point, and named in the detail."""
    from slopetui.queue.hysteresis_jobs import submit as submit_sweep
    from tests.unit.test_hysteresis_jobs import SPEC as SWEEP

    continuation(db)
    submit_sweep(db, SWEEP)
    cid = stored_curve(db)

    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            await branch_table(pilot, app)
            curve_table = app.screen.query_one("#curve-table", DataTable)
            await wait_until(pilot, lambda: curve_table.row_count == 1)
            assert app.screen.has_class("-three")
            row = cells(curve_table, 0)
            assert row[:5] == [str(cid), "fold", "(k, τ)", "done", "4"]
            assert row[5].startswith("bautin k=26.225")
            for table_id in ("#branch-table", "#hyst-table", "#curve-table"):
                assert app.screen.query_one(table_id).region.height >= 2
            curve_table.focus()
            plot = app.screen.query_one(PlotView)
            await wait_until(pilot, lambda: f"curve {cid}: fold of cycles" in str(plot.render()))
            drawn = str(plot.render())
            assert "fold of cycles 4" in drawn and "bautin 1" in drawn
            assert plot.region.height >= 11 and plot.region.bottom <= 23
            detail = str(app.screen.query_one("#branch-detail").render())
            assert "found: bautin k=26.2247 τ=0.64995" in detail
            assert "end: the amplitude vanished" in detail

    run(scenario)
