"""Marking runs and comparing them (m, v), and the figure key (f) on the sweeps, run
detail and compare screens (Pilot, 80x24)."""

from __future__ import annotations

from pathlib import Path

from textual.widgets import Static

from slopetui.plots.compare_plots import render_compare_phase, render_compare_time
from slopetui.store.database import Database
from slopetui.tui.screens.compare import TAB_PHASE, TAB_TIME, CompareScreen
from slopetui.tui.screens.run_detail import RunDetailScreen
from slopetui.tui.widgets.phase_grid import PhaseGrid
from slopetui.tui.widgets.plot_view import PlotView
from tests.support import finish_all, submit_quick
from tests.tui.support import run, wait_until
from tests.tui.test_tui_app import app_for, plane

#: A cold numba cache compiles the kernels first.
SETTLE_S = 120.0


def written(folder: Path, pattern: str) -> list[str]:
    return sorted(p.name for p in folder.glob(pattern))


def test_two_marked_runs_are_overlaid_and_their_figure_written(db: Database, tmp_path: Path):
    plane(db, nx=4, ny=2)
    finish_all(db)

    async def scenario():
        app = app_for(db)
        app.figure_folder = tmp_path
        async with app.run_test(size=(80, 24)) as pilot:
            grid = app.query_one(PhaseGrid)
            await wait_until(pilot, lambda: grid.data is not None)
            await pilot.press("v")  # nothing marked: says how, opens nothing
            await pilot.pause()
            assert not isinstance(app.screen, CompareScreen)
            await pilot.press("d", "m")
            first = grid.cursor_run()[0]
            await pilot.press("right", "right", "m")
            second = grid.cursor_run()[0]
            assert app.marked == [first, second]
            await pilot.press("m")  # m again unmarks
            assert app.marked == [first]
            await pilot.press("m", "v")
            await wait_until(pilot, lambda: isinstance(app.screen, CompareScreen))
            screen = app.screen
            await wait_until(pilot, lambda: len(screen.computed) == 2, SETTLE_S)
            status = str(screen.query_one("#compare-status", Static).content)
            assert status.startswith("2 runs recomputed"), status
            for key, tab in (("t", TAB_TIME), ("p", TAB_PHASE)):
                await pilot.press(key)
                await pilot.pause()
                await pilot.pause()
                drawn = str(screen.query_one(f"#{tab} PlotView", PlotView).content)
                assert f"run {first}: k " in drawn and f"run {second}: k " in drawn, drawn[-300:]
            await pilot.press("f")
            await wait_until(pilot, lambda: bool(written(tmp_path, "runs-*.pdf")), SETTLE_S)
            assert written(tmp_path, "runs-*") == [f"runs-{first}-{second}.csv",
                                                   f"runs-{first}-{second}.pdf"]
            assert (tmp_path / f"runs-{first}-{second}.pdf").read_bytes().startswith(b"%PDF")

    run(scenario)


def test_the_figure_key_never_overwrites_and_says_where(db: Database, tmp_path: Path):
    submit_quick(db, 2)
    finish_all(db)

    async def scenario():
        app = app_for(db)
        app.figure_folder = tmp_path
        async with app.run_test(size=(80, 24)) as pilot:
            await wait_until(pilot, lambda: app.screen.query("#bifurcation")
                             and app.screen.query_one("#bifurcation").diagram is not None)
            sweep = app.screen.selected
            await pilot.press("f")
            await wait_until(pilot, lambda: bool(written(tmp_path, "sweep-*.pdf")), SETTLE_S)
            await pilot.press("f")
            await wait_until(pilot, lambda: len(written(tmp_path, "sweep-*.pdf")) == 2, SETTLE_S)
            assert written(tmp_path, "sweep-*.pdf") == [f"sweep-{sweep}-2.pdf", f"sweep-{sweep}.pdf"]
            notes = [n.message for n in app._notifications]
            assert any(f"figure written: {tmp_path / f'sweep-{sweep}.pdf'}" in m for m in notes), notes

            await pilot.press("d", "enter")
            await wait_until(pilot, lambda: isinstance(app.screen, RunDetailScreen))
            detail = app.screen
            await wait_until(pilot, lambda: detail.traces is not None, SETTLE_S)
            await pilot.press("f")
            await wait_until(pilot, lambda: bool(written(tmp_path, "run-*.pdf")), SETTLE_S)
            assert written(tmp_path, "run-*") == [f"run-{detail.run_id}.csv", f"run-{detail.run_id}.pdf"]

    run(scenario)


def test_the_overlays_keep_runs_apart_without_colour():
    import numpy as np

    from slopetui.plots.compare_plots import Overlay

    t = np.linspace(0.0, 100.0, 5000)
    runs = [Overlay("run 1: k 10 (oscillatory)", t, 0.1 * t, np.sin(t)),
            Overlay("run 2: k 12 (complex)", t, 0.1 * t + np.cos(t), np.sin(2 * t) + 3.0)]
    for render in (render_compare_time, render_compare_phase):
        text = render(runs, width=80, height=24, color=False)
        lines = text.split("\n")
        assert len(lines) == 24 and max(map(len, lines)) <= 80
        assert "\x1b[" not in text
        legend = lines[-1] if "run 2" in lines[-1] else "\n".join(lines[-2:])
        assert "run 1: k 10 (oscillatory)" in text and "run 2: k 12 (complex)" in legend
        assert "•" in text  # the second run's marker, not braille: apart with colour off


def test_the_overlaid_time_series_shows_the_last_periods_of_the_slowest_run():
    import numpy as np

    from slopetui.plots.compare_plots import Overlay
    from slopetui.plots.run_plots import TIME_PERIODS, recent_start

    t = np.linspace(0.0, 1000.0, 100_001)
    slow, fast = 0.1, 0.25  # periods 10 and 4
    runs = [Overlay("run 1", t, 0.1 * t, np.sin(2 * np.pi * fast * t), fast),
            Overlay("run 2", t, 0.1 * t, np.sin(2 * np.pi * slow * t), slow)]
    assert recent_start([t, t], [1 / fast, 1 / slow]) == 1000.0 - TIME_PERIODS / slow
    text = render_compare_time(runs, width=80, height=24, color=False)
    assert f"t (the last {TIME_PERIODS} periods)" in text
    ticks = text.split("\n")[-3]  # the x tick labels, over the axis label and the legend
    assert "900" in ticks and "1000" in ticks and "500" not in ticks, ticks
    # no period (a fixed point, or no frequency): the whole window
    rest = [Overlay("run 1", t, np.zeros_like(t), np.zeros_like(t), float("nan"))]
    assert "the last" not in render_compare_time(rest, width=80, height=24, color=False)
