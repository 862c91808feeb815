"""Where a phase grid's runs go on screen: how many lattice points a display block holds,
how many characters wide a block is, whether two rows of blocks share a character (half
blocks, slopetui.plots.lattice_cells), and which blocks are in view.

Two ways to fit a lattice to the room (``z`` switches):

- *whole* (the default): blocks of sx x sy points, so that the whole lattice fits. With
  colour, half blocks double the rows: in the sweeps screen of a 120 x 40 terminal (111
  columns and 29 lines for the cells) a 100 x 100 lattice is 100 x 50 blocks of 1 x 2
  runs. Without colour, one marker per character: 100 x 25 blocks of 1 x 4.
- *full resolution*: one run per block, and the view follows the cursor over a lattice
  larger than the room, as a pager does: every run is drawn on its own, a part of the
  lattice at a time. There the sweep list makes way (34 lines for the cells): all 100
  columns and 68 of the 100 rows at once. No terminal of 40 lines shows 100 rows of
  runs at once: two per character is as many as a character has colours for.

A lattice that fits at one run per character is drawn that way either way: markers are
easier to read than colours alone.
"""

from __future__ import annotations

from dataclasses import dataclass

#: Characters per block at most: a small lattice is widened, not drawn in a corner.
MAX_CELL_WIDTH = 3


def _ceil_div(a: int, b: int) -> int:
    return -(-a // b)


@dataclass(frozen=True)
class GridView:
    """The blocks of a lattice and the part of them in view. Block coordinates are
    (col, row), row 0 at the bottom; ``cols`` x ``rows`` cover the whole lattice, of which
    ``view_cols`` x ``view_rows`` from (col0, row0) up are in view."""

    half: bool
    cell_w: int
    sx: int
    sy: int
    cols: int
    rows: int
    col0: int = 0
    row0: int = 0
    view_cols: int = 0
    view_rows: int = 0

    @property
    def text_rows(self) -> int:
        """Lines the blocks in view take."""
        return _ceil_div(self.view_rows, 2) if self.half else self.view_rows

    @property
    def clipped(self) -> bool:
        """Not every block is in view."""
        return self.view_cols < self.cols or self.view_rows < self.rows

    def clamp(self, col: int, row: int) -> tuple[int, int]:
        return min(max(col, 0), self.cols - 1), min(max(row, 0), self.rows - 1)


def _follow(first: int, shown: int, total: int, at: int) -> int:
    """The first block in view along one axis: moved as little as puts ``at`` in view."""
    first = min(max(first, at - shown + 1), at)
    return min(max(first, 0), max(total - shown, 0))


def place(nx: int, ny: int, width: int, height: int, *, colour: bool, full: bool,
          cursor: tuple[int, int], origin: tuple[int, int]) -> GridView:
    """The view of an nx x ny lattice in ``width`` columns and ``height`` lines: whole, or
    with ``full`` at full resolution, the view moved from ``origin`` (the first block in
    view before) as little as keeps ``cursor`` (a block) in it."""
    width, height = max(width, 1), max(height, 1)
    sx = 1 if full else _ceil_div(nx, width)
    cols = _ceil_div(nx, sx)
    cell_w = max(1, min(MAX_CELL_WIDTH, width // cols))
    half = colour and ny > height
    room = 2 * height if half else height
    sy = 1 if full else _ceil_div(ny, room)
    rows = _ceil_div(ny, sy)
    view_cols, view_rows = min(cols, width // cell_w), min(rows, room)
    col = min(max(cursor[0], 0), cols - 1)
    row = min(max(cursor[1], 0), rows - 1)
    return GridView(half, cell_w, sx, sy, cols, rows,
                    _follow(origin[0], view_cols, cols, col),
                    _follow(origin[1], view_rows, rows, row), view_cols, view_rows)
