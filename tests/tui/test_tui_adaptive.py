"""Adaptive phase diagrams in the application: the sweeps screen draws a refined sweep with
its counts, and the new-sweep form submits an adaptive one (the rest of adaptive sweeps:
tests/unit/test_adaptive.py)."""

from __future__ import annotations

from sqlalchemy import func, select

from slopetui.store.models import Run, Sweep
from slopetui.store.open import open_store
from slopetui.sweeps.diagram import load_diagram
from slopetui.tui.app import SlopeApp
from slopetui.tui.screens.sweeps import SweepsScreen
from slopetui.tui.widgets.phase_grid import PhaseGrid
from tests.tui.support import fill, open_form, run, wait_until


def test_the_application_draws_an_adaptive_sweep_and_the_form_submits_one(refined):
    # it adds a sweep to the module's store: the last (only) test that uses it
    url, sweep_id = refined
    db = open_store(url)
    diagram = load_diagram(db, sweep_id)

    async def scenario():
        app = SlopeApp(url, start_workers=False, refresh_s=60)
        async with app.run_test(size=(80, 24)) as pilot:
            grid = app.query_one(PhaseGrid)
            await wait_until(pilot, lambda: grid.data is not None)
            shown = str(grid.render())
            assert (f"adaptive: {diagram.n_computed} computed, {diagram.n_inferred} "
                    "inferred") in shown
            assert grid.data.inferred == {(r.ix, r.iy) for r in diagram.runs if r.inferred}
            form = await open_form(app, pilot)
            fill(app, {"x-param": "k", "x-start": "3", "x-stop": "9", "x-num": "17",
                       "y-param": "tau", "y-start": "1", "y-stop": "4", "y-num": "17",
                       "solver-method": "rk4", "solver-dt": "0.01", "solver-t_end": "100",
                       "solver-window": "50", "adaptive-levels": "9"})
            await pilot.pause()
            assert "adaptive.levels" in str(form.query_one("#form-error").render())
            assert form.query_one("#adaptive-levels").has_class("-invalid")
            fill(app, {"adaptive-levels": "3"})
            await pilot.pause()
            assert "9 coarse runs" in str(form.query_one("#estimate").render())
            await pilot.press("ctrl+s")
            await wait_until(pilot, lambda: isinstance(app.screen, SweepsScreen))
        with db.sessions() as s:
            sweep = s.scalars(select(Sweep).order_by(Sweep.id.desc())).first()
            n = s.scalar(select(func.count()).select_from(Run).where(Run.sweep_id == sweep.id))
        assert (sweep.adaptive_levels, sweep.level, sweep.n_runs, n) == (3, 0, 17 * 17, 9)

    run(scenario)
