"""The new-sweep form's stop rule: certified unless changed, saying so and why; a preset
sets the paper's t_end; the runs queued carry the rule chosen."""

from __future__ import annotations

from sqlalchemy import select
from textual.widgets import Select

from slopetui.store.models import Run
from slopetui.tui.screens.sweeps import SweepsScreen
from tests.tui.support import fill, open_form, run, wait_until
from tests.tui.test_tui_app import app_for

SMALL = {"x-param": "k", "x-start": "3", "x-stop": "9", "x-num": "2",
         "y-param": "tau", "y-start": "1", "y-stop": "4", "y-num": "2",
         "solver-method": "rk4", "solver-dt": "0.01", "solver-t_end": "500",
         "solver-window": "100"}


def test_the_form_defaults_to_certified_and_says_why(db):
    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            form = await open_form(app, pilot)
            assert form.query_one("#solver-stop", Select).value == "certified"
            note = str(form.query_one("#stop-note").render())
            assert "stop: certified (the default)" in note and "paper's protocol" in note
            fill(app, SMALL)
            await pilot.pause()
            # an empty store: no certified run to take stopping times from
            assert "assumes t_end: no certified run on this store yet" \
                in str(form.query_one("#estimate").render())
            await pilot.press("ctrl+s")
            await wait_until(pilot, lambda: isinstance(app.screen, SweepsScreen))
        with db.sessions() as s:
            assert set(s.scalars(select(Run.stop))) == {"certified"}

    run(scenario)


def test_a_preset_sets_t_end_and_the_field_goes_on_the_runs(db):
    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            form = await open_form(app, pilot)
            form.query_one("#preset", Select).value = "fig4a"
            await pilot.pause()
            assert form.query_one("#solver-stop", Select).value == "t_end"
            assert "every run to t_end" in str(form.query_one("#estimate").render())
            fill(app, SMALL)  # a smaller sweep than the preset's, its stop rule kept
            await pilot.pause()
            assert form.spec is not None and form.spec.solver.stop == "t_end"
            await pilot.press("ctrl+s")
            await wait_until(pilot, lambda: isinstance(app.screen, SweepsScreen))
        with db.sessions() as s:
            assert set(s.scalars(select(Run.stop))) == {"t_end"}

    run(scenario)
