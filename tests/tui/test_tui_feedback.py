"""Keys that did nothing visible, or too much without asking: z on a lattice already at
one run per cell, ctrl+q in a filled form; and the queue screen's line on the runs the
workers hold."""

from __future__ import annotations

import numpy as np
from textual.widgets import Input, Static

from slopetui.queue import jobs
from slopetui.tui.app import SlopeApp
from slopetui.tui.screens.confirm import ConfirmScreen
from slopetui.tui.screens.new_sweep import NewSweepScreen
from slopetui.tui.screens.queue import QueueScreen
from slopetui.tui.widgets.phase_grid import GridData, PhaseGrid
from tests.support import submit_quick
from tests.tui.support import open_form, run, wait_until
from tests.tui.test_tui_scale import GridApp, lattice


def small_lattice() -> GridData:
    runs = {(ix, iy): (1 + iy * 6 + ix, "sliding") for iy in range(4) for ix in range(6)}
    return GridData("k", "tau", np.linspace(2, 20, 6), np.linspace(0.5, 10, 4), False, False,
                    runs)


def test_z_on_a_small_lattice_says_why_nothing_zooms():
    async def scenario():
        app = GridApp(small_lattice())
        async with app.run_test(size=(120, 33)) as pilot:
            grid = app.query_one(PhaseGrid)
            grid.focus()
            await pilot.pause()
            view = grid.view()
            assert (view.sx, view.sy) == (1, 1)
            await pilot.press("z")
            await pilot.pause()
            assert not grid.full
            said = [n.message for n in app._notifications]
            assert len(said) == 1 and "6 x 4 lattice has its own cell already" in said[0]

    run(scenario)


def test_z_on_a_large_lattice_zooms_without_a_notice():
    async def scenario():
        app = GridApp(lattice()[0])
        async with app.run_test(size=(120, 33)) as pilot:
            grid = app.query_one(PhaseGrid)
            grid.focus()
            await pilot.pause()
            await pilot.press("z")
            await pilot.pause()
            assert grid.full and not list(app._notifications)
            await pilot.press("z")
            await pilot.pause()
            assert not grid.full

    run(scenario)


def app_for(db) -> SlopeApp:
    return SlopeApp(db.display_url, start_workers=False, refresh_s=0.2)


def test_ctrl_q_in_a_filled_form_asks_first_and_keep_keeps_it(db):
    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(120, 40)) as pilot:
            form = await open_form(app, pilot)
            form.query_one("#x-stop", Input).value = "30"
            await pilot.pause()
            await pilot.press("ctrl+q")
            await wait_until(pilot, lambda: isinstance(app.screen, ConfirmScreen))
            question = app.screen.question
            assert question.startswith("Quit slopetui? The new sweep's form")
            assert "(x stop) would be lost" in question
            await pilot.press("n")  # keep editing
            await wait_until(pilot, lambda: isinstance(app.screen, NewSweepScreen))
            assert app.return_code is None
            assert form.query_one("#x-stop", Input).value == "30"
            await pilot.press("ctrl+q")
            await wait_until(pilot, lambda: isinstance(app.screen, ConfirmScreen))
            await pilot.press("y")
            await wait_until(pilot, lambda: app.return_code is not None)
        assert app.return_code == 0

    run(scenario)


def test_ctrl_q_in_an_untouched_form_quits_at_once(db):
    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(120, 40)) as pilot:
            await open_form(app, pilot)
            await pilot.press("ctrl+q")
            await wait_until(pilot, lambda: app.return_code is not None)
        assert app.return_code == 0

    run(scenario)


def test_the_queue_screen_says_runs_are_claimed_in_batches(db):
    submit_quick(db, 5)
    batch = jobs.claim_batch(db, "w", 4)
    jobs.begin(db, batch[:1], "w")

    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(120, 40)) as pilot:
            await wait_until(pilot, lambda: app.db is not None)
            await pilot.press("2")
            line = lambda: str(app.screen.query_one("#queue-claimed", Static).render())  # noqa: E731
            await wait_until(pilot, lambda: isinstance(app.screen, QueueScreen)
                             and "held" in line())
            assert line() == ("4 runs held by no live worker: queued again when their lease "
                              "runs out")

    run(scenario)
