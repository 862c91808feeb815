"""Pilot tests of the analysis forms (slopetui.tui.screens.analysis_form, analyses): a
continuation and a hysteresis sweep from the Branches screen (keys c and h), an orbit
computed in the background, a certified re-run from the palette. Valid input queues the
job (read back from the store); a bad field is named and marked and queues nothing; Esc or
ctrl+q on a filled form asks first."""

from __future__ import annotations

import pytest
from textual.widgets import Input, Static

from slopetui.store.queries import runs_matching
from slopetui.sweeps.branches import listing as branch_listing
from slopetui.sweeps.hysteresis_runs import listing as hysteresis_listing
from slopetui.tui.app import SlopeApp
from slopetui.tui.commands import commands, typed_commands
from slopetui.tui.screens.analysis_form import AnalysisFormScreen
from slopetui.tui.screens.branches import EMPTY_HINT, BranchesScreen
from slopetui.tui.screens.confirm import ConfirmScreen
from tests.support import finish_all, submit_quick
from tests.tui.support import run, wait_until


def app_for(db) -> SlopeApp:
    return SlopeApp(db.display_url, start_workers=False, refresh_s=0.2)


async def form_from_branches(app: SlopeApp, pilot, key: str) -> AnalysisFormScreen:
    """Key 4 (the Branches screen), then ``key``; the form once composed."""
    await wait_until(pilot, lambda: app.db is not None)
    await pilot.press("4")
    await wait_until(pilot, lambda: isinstance(app.screen, BranchesScreen))
    await pilot.press(key)
    await wait_until(pilot, lambda: isinstance(app.screen, AnalysisFormScreen)
                     and bool(app.screen.query("#form-buttons")))
    return app.screen


def text_of(screen, widget_id: str) -> str:
    return str(screen.query_one(f"#{widget_id}", Static).render())


def set_field(screen, name: str, value: str) -> None:
    screen.query_one(f"#f-{name}", Input).value = value


def test_key_c_on_branches_queues_a_continuation(db):
    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            form = await form_from_branches(app, pilot, "c")
            set_field(form, "to", "1.5")
            set_field(form, "points", "40")
            await pilot.pause()
            assert "at most 40 points" in text_of(form, "estimate")
            await pilot.press("ctrl+s")
            await wait_until(pilot, lambda: isinstance(app.screen, BranchesScreen))
        (stored,) = branch_listing(db)
        assert (stored.row.param, stored.row.start, stored.row.end_value,
                stored.row.max_points, stored.row.status) == ("k", "hopf", 1.5, 40, "queued")

    run(scenario)


def test_a_bad_continuation_field_is_named_and_queues_nothing(db):
    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            form = await form_from_branches(app, pilot, "c")
            set_field(form, "points", "1")
            await pilot.pause()
            assert "points = 1 is out of range: allowed an integer from 2 to 5000" in \
                text_of(form, "form-error")
            assert form.query_one("#f-points").has_class("-invalid")
            await pilot.press("ctrl+s")
            await pilot.pause(0.3)
            assert app.screen is form
        assert branch_listing(db) == []

    run(scenario)


def test_key_h_on_branches_queues_a_hysteresis_sweep(db):
    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            form = await form_from_branches(app, pilot, "h")
            set_field(form, "from", "5")
            set_field(form, "to", "9")
            set_field(form, "points", "5")
            await pilot.pause()
            assert "10 points (up and down)" in text_of(form, "estimate")
            await pilot.press("ctrl+s")
            await wait_until(pilot, lambda: isinstance(app.screen, BranchesScreen))
        (stored,) = hysteresis_listing(db)
        assert (stored.row.param, stored.row.start, stored.row.stop, stored.row.n_points) == \
            ("k", 5.0, 9.0, 5)

    run(scenario)


def test_a_bad_hysteresis_field_is_named_and_queues_nothing(db):
    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            form = await form_from_branches(app, pilot, "h")
            set_field(form, "to", form.query_one("#f-from", Input).value)
            await pilot.pause()
            assert "to = " in text_of(form, "form-error")
            assert form.query_one("#f-to").has_class("-invalid")
            await pilot.press("ctrl+s")
            await pilot.pause(0.3)
        assert hysteresis_listing(db) == []

    run(scenario)


def test_esc_on_a_filled_form_asks_and_keep_keeps_it(db):
    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            form = await form_from_branches(app, pilot, "h")
            set_field(form, "points", "7")
            await pilot.pause()
            await pilot.press("escape")
            await wait_until(pilot, lambda: isinstance(app.screen, ConfirmScreen))
            assert "(points) would be lost" in app.screen.question
            await pilot.press("n")
            await wait_until(pilot, lambda: app.screen is form)
            assert form.query_one("#f-points", Input).value == "7"
            await pilot.press("ctrl+q")
            await wait_until(pilot, lambda: isinstance(app.screen, ConfirmScreen))
            assert app.screen.question.startswith("Quit slopetui? The hysteresis sweep form")
            await pilot.press("n")
            await wait_until(pilot, lambda: app.screen is form)
            await pilot.press("escape")
            await wait_until(pilot, lambda: isinstance(app.screen, ConfirmScreen))
            await pilot.press("y")
            await wait_until(pilot, lambda: isinstance(app.screen, BranchesScreen))
            assert app.return_code is None

    run(scenario)


def test_esc_on_an_untouched_form_closes_it(db):
    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            await form_from_branches(app, pilot, "c")
            await pilot.press("escape")
            await wait_until(pilot, lambda: isinstance(app.screen, BranchesScreen))

    run(scenario)


def test_the_branches_hint_names_the_keys_not_the_cli():
    assert "c queues one" in EMPTY_HINT and "slopetui continue" not in EMPTY_HINT


def test_every_analysis_has_a_palette_entry(db):
    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            await wait_until(pilot, lambda: app.db is not None)
            names = [c.name.lower() for c in commands(app, app.screen)]
            for word in ("continuation", "hysteresis", "orbit", "certified re-run"):
                assert any(word in name for name in names), word

    run(scenario)


def test_a_certified_rerun_from_the_palette_queues_the_run_again(db):
    submit_quick(db, 2, stop="t_end")
    finish_all(db)
    run_id = runs_matching(db, sweep=1)[0].id

    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            await wait_until(pilot, lambda: app.db is not None)
            (command,) = typed_commands(app, f"rerun run {run_id}")
            command.run()
            await wait_until(pilot, lambda: isinstance(app.screen, AnalysisFormScreen)
                             and bool(app.screen.query("#form-buttons")))
            form = app.screen
            assert "stops where its attractor is certified" in text_of(form, "estimate")
            set_field(form, "run", "999")
            await pilot.pause()
            assert "run: no run 999" in text_of(form, "form-error")
            await pilot.press("ctrl+s")
            await pilot.pause(0.3)
            assert len(runs_matching(db)) == 2  # nothing queued
            set_field(form, "run", str(run_id))
            await pilot.pause()
            await pilot.press("ctrl+s")
            await wait_until(pilot, lambda: not isinstance(app.screen, AnalysisFormScreen))
        (again,) = runs_matching(db, sweep=2)
        assert again.stop == "certified" and again.k == runs_matching(db, sweep=1)[0].k

    run(scenario)


def test_the_orbit_form_computes_in_the_background_and_shows_the_multipliers(db):
    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(100, 40)) as pilot:
            await wait_until(pilot, lambda: app.db is not None)
            app.open_analysis("orbit")
            await wait_until(pilot, lambda: isinstance(app.screen, AnalysisFormScreen)
                             and bool(app.screen.query("#form-buttons")))
            form = app.screen
            set_field(form, "t-seed", "10")
            await pilot.pause()
            assert "t-seed = '10' is out of range" in text_of(form, "form-error")
            set_field(form, "k", "10")
            set_field(form, "tau", "10")
            set_field(form, "t-seed", "300")
            await pilot.pause()
            await pilot.press("ctrl+s")
            await wait_until(pilot, lambda: "|mu|" in text_of(form, "result")
                             or "no orbit" in text_of(form, "result"), timeout=180)
            shown = text_of(form, "result")
            assert "period " in shown and "multipliers outside the unit circle" in shown
            assert "step check at dt 0.005: " in shown and "1 maximum a period: resolved" in shown
            assert app.screen is form  # it stays open on the result

    run(scenario)


def test_the_orbit_form_opens_at_the_diagram_cursors_point(db):
    from slopetui.tui.widgets.phase_grid import PhaseGrid
    from tests.tui.test_tui_app import plane
    plane(db)

    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            grid = app.query_one(PhaseGrid)
            await wait_until(pilot, lambda: grid.data is not None and bool(grid.data.runs))
            await pilot.press("d")  # into the diagram
            await wait_until(pilot, lambda: grid.has_focus)
            for key in ("right", "right", "down"):
                await pilot.press(key)
            await pilot.pause()
            at = grid.cursor_run()
            assert at is not None
            _run, k, tau, _label = at
            (entry,) = [c for c in commands(app, app.screen) if "orbit at the cursor" in c.name]
            entry.run()
            await wait_until(pilot, lambda: isinstance(app.screen, AnalysisFormScreen)
                             and bool(app.screen.query("#form-buttons")))
            form = app.screen
            assert float(form.query_one("#f-k", Input).value) == pytest.approx(k, rel=1e-5)
            assert float(form.query_one("#f-tau", Input).value) == pytest.approx(tau, rel=1e-5)
            assert (k, tau) != (2.0, 0.5)  # the cursor moved off the first run

    run(scenario)


def test_an_orbit_form_closed_while_computing_says_the_result_in_a_notification(db, monkeypatch):
    import threading

    from core.orbit import OrbitError
    from slopetui.sweeps import orbit_point
    release = threading.Event()

    def held(*_args):  # the computation ends only once the form is closed
        release.wait(30)
        raise OrbitError("none here (held by the test)")

    monkeypatch.setattr(orbit_point, "compute_orbit", held)

    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            await wait_until(pilot, lambda: app.db is not None)
            app.open_analysis("orbit")
            await wait_until(pilot, lambda: isinstance(app.screen, AnalysisFormScreen)
                             and bool(app.screen.query("#form-buttons")))
            form = app.screen
            await pilot.press("ctrl+s")
            assert form.busy and "computing" in text_of(form, "result")
            app.pop_screen()
            await wait_until(pilot, lambda: form not in app.screen_stack)
            release.set()
            await wait_until(pilot, lambda: any("no orbit: none here" in str(n.message)
                                                for n in app._notifications))
            assert app.return_code is None  # no traceback quit the application

    run(scenario)


def test_a_form_opened_on_branches_starts_at_the_highlighted_jobs_point(db):
    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            form = await form_from_branches(app, pilot, "c")
            set_field(form, "k", "12.5")
            set_field(form, "tau", "7")
            await pilot.pause()
            await pilot.press("ctrl+s")
            await wait_until(pilot, lambda: isinstance(app.screen, BranchesScreen)
                             and app.screen.analysis_point() is not None)
            await pilot.press("h")
            await wait_until(pilot, lambda: isinstance(app.screen, AnalysisFormScreen)
                             and bool(app.screen.query("#form-buttons")))
            values = app.screen.values()
            assert (values["k"], values["tau"], values["from"], values["to"]) == \
                ("12.5", "7", "10", "15")

    run(scenario)
