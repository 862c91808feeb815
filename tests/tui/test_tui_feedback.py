"""Keys that did nothing visible, or too much without asking: z on a lattice already at
one run per cell, ctrl+q in a filled form; and the queue screen's line on the runs the
workers hold."""

from __future__ import annotations

import numpy as np

from slopetui.tui.widgets.phase_grid import GridData, PhaseGrid
from tests.tui.support import run
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
