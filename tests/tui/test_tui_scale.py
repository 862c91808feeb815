"""The application with large sweeps: the sweeps screen reads nothing while
another screen covers it and only what changed while in view, and a 100 x 100 lattice
is drawn at full resolution in half blocks, in markers without colour."""

from __future__ import annotations

from dataclasses import replace
from datetime import datetime

import numpy as np
from sqlalchemy import update
from textual.app import App, ComposeResult

from slopetui.plots.lattice_cells import LOWER, UPPER
from slopetui.plots.regime_colors import BLOCK_COLORS
from slopetui.store.models import Run
from slopetui.sweeps import live_diagram
from slopetui.sweeps.spec import parse_spec
from slopetui.sweeps.submit import submit
from slopetui.tui.app import SlopeApp
from slopetui.tui.screens import sweeps as sweeps_screen
from slopetui.tui.screens.queue import QueueScreen
from slopetui.tui.screens.sweeps import SweepsScreen
from slopetui.tui.widgets.phase_grid import LABEL_WIDTH, GridData, PhaseGrid
from tests.support import QUICK_SOLVER, finish_all
from tests.tui.support import run, wait_until
from tests.unit.test_scale_live_diagram import finish


def plane(db, nx: int = 6, ny: int = 4) -> int:
    spec = parse_spec({"x": {"param": "k", "start": 2, "stop": 20, "num": nx},
                       "y": {"param": "tau", "start": 0.5, "stop": 10, "num": ny},
                       "solver": QUICK_SOLVER})
    return submit(db, spec).sweep_id


def test_a_hidden_sweeps_screen_reads_nothing_and_catches_up_when_shown(db, monkeypatch):
    plane(db)
    finish_all(db)
    calls: list[str] = []
    real = sweeps_screen.sweep_progress

    def counted(*args, **kwargs):
        calls.append("read")
        return real(*args, **kwargs)

    monkeypatch.setattr(sweeps_screen, "sweep_progress", counted)

    async def scenario():
        app = SlopeApp(db.display_url, start_workers=False, refresh_s=0.05)
        async with app.run_test(size=(80, 24)) as pilot:
            grid = app.query_one(PhaseGrid)
            await wait_until(pilot, lambda: grid.data is not None and len(calls) >= 3)
            await pilot.press("2")
            await wait_until(pilot, lambda: isinstance(app.screen, QueueScreen))
            await pilot.pause(0.3)  # a load already started may still land
            hidden = len(calls)
            await pilot.pause(1.0)  # 20 refresh periods
            assert len(calls) == hidden, "the hidden sweeps screen read the store"
            await pilot.press("1")
            await wait_until(pilot, lambda: isinstance(app.screen, SweepsScreen))
            await wait_until(pilot, lambda: len(calls) > hidden)  # caught up at once

    run(scenario)


def test_runs_finished_after_the_first_read_show_and_older_ones_are_not_read_again(
        db, monkeypatch):
    sweep = plane(db)
    old = finish(db, 12)
    with db.transaction() as s:  # finished long ago: outside the re-read margin
        s.execute(update(Run).where(Run.id.in_(old)).values(finished_at=datetime(2000, 1, 1)))
    reads: list[set[int]] = []
    real = live_diagram.read_diagram

    def spy(*args, **kwargs):
        read = real(*args, **kwargs)
        reads.append({row.id for row in read.rows})
        return read

    monkeypatch.setattr(live_diagram, "read_diagram", spy)

    async def scenario():
        app = SlopeApp(db.display_url, start_workers=False, refresh_s=0.1)
        async with app.run_test(size=(80, 24)) as pilot:
            grid = app.query_one(PhaseGrid)
            await wait_until(pilot, lambda: grid.data is not None)
            assert sum(label is not None for _, label in grid.data.runs.values()) == 12
            new = finish(db, 12)  # a worker elsewhere finishes the rest
            await wait_until(pilot, lambda: None not in {r for _, r in grid.data.runs.values()})
            assert len(reads[0]) == 24  # the first read: the whole sweep, once
            later = set().union(*reads[1:])
            assert later == set(new) and not later & set(old)
            assert app.screen._live[sweep].whole_reads == 1

    run(scenario)


def test_an_idle_sweeps_screen_reads_nothing_with_a_sweep_below_the_first_selected(
        db, monkeypatch):
    """With any sweep but the table's first selected, each refill of the table selected
    and loaded the first sweep, then the selected one again: two reads whose sweeps had
    changed (their rates), another refill, and so on, a whole core on an idle screen
    (SweepsScreen._fill_table)."""
    first, second = plane(db, 6, 4), plane(db, 5, 3)
    finish_all(db)
    reads: list[int] = []
    real = sweeps_screen.sweep_progress

    def changing(*args, **kwargs):
        # each read differs from the last, as while workers compute (the rate moves)
        reads.append(1)
        return [replace(p, runs_per_min=p.runs_per_min + len(reads))
                for p in real(*args, **kwargs)]

    monkeypatch.setattr(sweeps_screen, "sweep_progress", changing)

    async def scenario():
        app = SlopeApp(db.display_url, start_workers=False, refresh_s=60.0)
        async with app.run_test(size=(80, 24)) as pilot:
            grid = app.query_one(PhaseGrid)
            table = app.screen.query_one("#sweep-table")
            await wait_until(pilot, lambda: grid.data is not None)
            assert app.screen.selected == second  # the newest sweep, the first row
            await pilot.press("down")  # the second row: the first sweep submitted
            await pilot.pause(0.5)  # its diagram is read and drawn
            before = len(reads)
            await pilot.pause(1.0)  # idle: the next refresh is a minute away
            assert len(reads) - before <= 1, f"{len(reads) - before} reads in an idle second"
            assert app.screen.selected == first and table.cursor_row == 1
            assert len(grid.data.xs) == 6  # the first sweep's diagram, still

    run(scenario)


class GridApp(App[None]):
    """A phase grid alone, at the sweeps screen's width."""

    def __init__(self, data: GridData) -> None:
        super().__init__()
        self.data = data

    def compose(self) -> ComposeResult:
        yield PhaseGrid(id="grid")

    def on_mount(self) -> None:
        self.query_one(PhaseGrid).set_data(self.data)


def lattice(n: int = 100) -> tuple[GridData, np.ndarray]:
    """An n x n (k, tau) lattice of sliding and oscillatory runs in stripes three rows
    high, and which is which by [iy, ix]."""
    oscillating = np.broadcast_to((np.arange(n)[:, None] // 3) % 2 == 1, (n, n))
    runs = {(ix, iy): (1 + iy * n + ix, "oscillatory" if oscillating[iy, ix] else "sliding")
            for iy in range(n) for ix in range(n)}
    data = GridData("k", "tau", np.linspace(2, 20, n), np.linspace(0.5, 10, n), False, False,
                    runs)
    return data, oscillating


def half_block_colours(grid: PhaseGrid) -> dict[tuple[int, int], str | None]:
    """The colour the grid shows for each run in view, (ix, iy) -> colour, read back from
    its half blocks (a character: the upper run's colour, then the lower's)."""
    view = grid.view()
    text = grid.render()
    style_at: list = [None] * len(text.plain)
    for span in text.spans:
        style_at[span.start:span.end] = [span.style] * (span.end - span.start)
    shown = {}
    starts = [0, *(i + 1 for i, ch in enumerate(text.plain) if ch == "\n")]
    for t in range(view.text_rows):
        for i in range(view.view_cols):
            offset = starts[t] + LABEL_WIDTH + i * view.cell_w
            char, style = text.plain[offset], style_at[offset]
            fg = style.color.name if style.color else None
            bg = style.bgcolor.name if style.bgcolor else None
            upper, lower = {UPPER: (fg, bg), LOWER: (bg, fg), " ": (bg, bg)}[char]
            top = view.row0 + view.view_rows - 1 - (2 * t - view.view_rows % 2)
            for row, colour in ((top, upper), (top - 1, lower)):
                if view.row0 <= row < view.row0 + view.view_rows:
                    shown[(view.col0 + i, row)] = colour
    return shown


def test_a_100_by_100_lattice_at_120_by_40_shows_every_run_in_half_blocks(monkeypatch):
    monkeypatch.delenv("NO_COLOR", raising=False)
    data, oscillating = lattice()
    expected = {(ix, iy): BLOCK_COLORS["oscillatory" if oscillating[iy, ix] else "sliding"]
                for iy in range(100) for ix in range(100)}

    async def scenario():
        app = GridApp(data)
        async with app.run_test(size=(120, 33)) as pilot:  # the sweeps screen's 32-line pane
            grid = app.query_one(PhaseGrid)
            await pilot.pause()
            view = grid.view()
            # the whole lattice: every column, two runs a half block
            assert view.half and (view.sx, view.sy, view.cols, view.rows) == (1, 2, 100, 50)
            await pilot.press("z")  # full resolution: one run a half block, the view moving
            await pilot.pause()
            seen: dict[tuple[int, int], str | None] = {}
            cursors = set()
            for _ in range(2):  # the lowest rows in view, then the cursor to the top
                view = grid.view()
                assert (view.sx, view.sy, view.view_cols, view.half) == (1, 1, 100, True)
                cursors.add(view.clamp(*grid.cursor))  # drawn in the cursor's colour
                seen.update((p, c) for p, c in half_block_colours(grid).items()
                            if p not in cursors)
                grid.cursor = (0, 99)
                await pilot.pause()
            assert seen.keys() | cursors >= expected.keys()  # every run came into view
            assert all(seen[p] == expected[p] for p in seen)  # each in its regime's colour

    run(scenario)


def test_without_colour_the_lattice_is_drawn_in_markers(monkeypatch):
    monkeypatch.setenv("NO_COLOR", "1")
    data, _ = lattice()

    async def scenario():
        app = GridApp(data)
        async with app.run_test(size=(120, 33)) as pilot:
            grid = app.query_one(PhaseGrid)
            await pilot.pause()
            view = grid.view()
            assert not view.half and view.sy > 1  # blocks of runs, one marker each
            cells = "".join(line[LABEL_WIDTH:LABEL_WIDTH + view.view_cols]
                            for line in grid.render().plain.split("\n")[:view.text_rows])
            assert UPPER not in cells and LOWER not in cells
            assert set(cells) == {".", "o"}  # sliding and oscillatory, by their markers

    run(scenario)


def test_the_grid_shows_the_selected_sweep_after_quick_moves_between_sweeps(db):
    first = plane(db, 6, 4)
    second = plane(db, 5, 3)
    finish_all(db)
    sizes = {first: 6, second: 5}

    async def scenario():
        app = SlopeApp(db.display_url, start_workers=False, refresh_s=0.1)
        async with app.run_test(size=(80, 24)) as pilot:
            grid = app.query_one(PhaseGrid)
            await wait_until(pilot, lambda: grid.data is not None)
            for _ in range(4):  # each move loads the other sweep's diagram, kept since
                await pilot.press("down", "up", "down")
            screen = app.screen
            await pilot.pause(0.5)
            await wait_until(pilot, lambda: len(grid.data.xs) == sizes[screen.selected])
            await pilot.pause(0.5)  # and it stays so
            assert len(grid.data.xs) == sizes[screen.selected]

    run(scenario)


def test_a_late_load_of_the_sweep_selected_before_does_not_replace_the_diagram(db):
    """load() is exclusive, but a worker it replaced still posts what it read: after fast
    cursor moves, the sweep selected before must not be drawn over the selected one."""
    first, second = plane(db, 6, 4), plane(db, 5, 3)
    finish_all(db)

    async def scenario():
        app = SlopeApp(db.display_url, start_workers=False, refresh_s=60.0)
        async with app.run_test(size=(80, 24)) as pilot:
            grid = app.query_one(PhaseGrid)
            screen = app.screen
            await wait_until(pilot, lambda: grid.data is not None)
            late = SweepsScreen.Loaded(screen._sweeps, screen._shown, grid.data)  # second's
            await pilot.press("down")
            await wait_until(pilot, lambda: grid.data is not None and len(grid.data.xs) == 6)
            screen.post_message(late)
            await pilot.pause(0.3)
            assert screen.selected == first and len(grid.data.xs) == 6
            assert late.diagram is not None and late.diagram.id == second

    run(scenario)
