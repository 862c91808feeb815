"""A 100 x 100 lattice at full resolution in a 120 x 40 terminal: two lattice
rows per character in half blocks (slopetui.plots.lattice_cells), blocks of runs where
the room is smaller, and where each block goes on screen (tui.widgets.grid_view)."""

from __future__ import annotations

import numpy as np
import pytest

from slopetui.plots.lattice_cells import (
    CODES,
    FULL,
    LOWER,
    PENDING_CODE,
    UPPER,
    all_in_blocks,
    block_labels,
    half_blocks,
)
from slopetui.plots.regime_colors import BLOCK_COLORS, LEGEND_ORDER
from slopetui.tui.widgets.grid_view import place

COLOURS = [BLOCK_COLORS[key] for key in LEGEND_ORDER]


def cells(rows):
    """The half-block rows as one (char, fg, bg) per character."""
    return [[(ch, fg, bg) for text, fg, bg in runs for ch in text] for runs in rows]


def decode(char, fg, bg):
    """The (upper, lower) colours a character shows."""
    return {FULL: (bg, bg), UPPER: (fg, bg), LOWER: (bg, fg)}[char]


def test_a_100_by_100_lattice_is_100_columns_by_50_lines_each_half_its_run():
    rng = np.random.default_rng(17)
    codes = rng.integers(0, len(CODES), size=(100, 100)).astype(np.int8)  # [iy, ix]
    # top line first: the lattice's highest row (iy = 99) is the first pixel row
    pixels = [[COLOURS[c] for c in codes[iy]] for iy in range(99, -1, -1)]
    drawn = cells(half_blocks(pixels))
    assert len(drawn) == 50 and {len(line) for line in drawn} == {100}
    for line, (upper_iy, lower_iy) in enumerate((99 - 2 * t, 98 - 2 * t) for t in range(50)):
        for ix in range(100):
            assert decode(*drawn[line][ix]) == (COLOURS[codes[upper_iy, ix]],
                                                COLOURS[codes[lower_iy, ix]])


def test_neighbours_of_one_colour_are_one_run_and_an_odd_count_leaves_the_top_half_empty():
    rows = half_blocks([["cyan", "cyan", "green"],
                        ["cyan", "cyan", "red"],
                        ["green", "green", "green"]])
    # an empty row above: the first line shows the first row in its lower halves
    assert rows[0] == [(LOWER * 2, "cyan", None), (LOWER, "green", None)]
    assert rows[1] == [(UPPER * 2, "cyan", "green"), (UPPER, "red", "green")]


def test_a_block_shows_its_most_common_finished_label():
    sliding, osc, failed = CODES["sliding"], CODES["oscillatory"], CODES["failed"]
    codes = np.array([[sliding, osc, PENDING_CODE, PENDING_CODE],
                      [osc, osc, PENDING_CODE, failed]], dtype=np.int8)
    # 2 x 2 blocks: the left one mostly oscillatory; the right one pending but for one
    # failed run, which is what it shows (a run that will not finish is not pending)
    assert block_labels(codes, 2, 2).tolist() == [[osc, failed]]
    assert block_labels(codes[:, 2:3], 1, 2).tolist() == [[PENDING_CODE]]
    mask = np.array([[True, True, True], [True, False, True]])
    assert all_in_blocks(mask, 2, 2).tolist() == [[False, True]]  # a partial block too


@pytest.mark.parametrize(("colour", "full", "expect"), [
    # the sweeps screen of a 120 x 40 terminal: 111 columns, 29 lines for the cells
    (True, False, dict(half=True, sx=1, sy=2, cols=100, rows=50, view_rows=50)),
    (False, False, dict(half=False, sx=1, sy=4, cols=100, rows=25, view_rows=25)),
    # full resolution: every run its own half block, 58 of the 100 rows in view at once
    (True, True, dict(half=True, sx=1, sy=1, cols=100, rows=100, view_rows=58)),
])
def test_where_a_100_by_100_lattice_goes_at_120_by_40(colour, full, expect):
    view = place(100, 100, 111, 29, colour=colour, full=full, cursor=(0, 0), origin=(0, 0))
    assert {k: getattr(view, k) for k in expect} == expect
    assert view.view_cols == 100 and view.cell_w == 1


def test_at_full_resolution_the_view_follows_the_cursor_as_little_as_needed():
    view = place(100, 100, 111, 29, colour=True, full=True, cursor=(5, 99), origin=(0, 0))
    assert (view.row0, view.row0 + view.view_rows) == (42, 100)  # the top rows, cursor in
    moved = place(100, 100, 111, 29, colour=True, full=True, cursor=(5, 60), origin=(0, 42))
    assert moved.row0 == 42  # still in view: the view stays
    down = place(100, 100, 111, 29, colour=True, full=True, cursor=(5, 30), origin=(0, 42))
    assert down.row0 == 30  # just enough to show it


def test_every_key_and_overlay_has_a_half_block_colour_of_its_own():
    from slopetui.plots.regime_colors import BLOCK_CURSOR, BLOCK_FOLD, BLOCK_HOPF
    colours = [*BLOCK_COLORS.values(), BLOCK_HOPF, BLOCK_FOLD, BLOCK_CURSOR]
    assert set(BLOCK_COLORS) == set(LEGEND_ORDER)
    assert len(set(colours)) == len(colours)  # no marker in a half block: colour alone
