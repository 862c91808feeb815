"""The live phase diagram of a 2-D sweep: one terminal cell per run (or per block of
runs when the sweep is larger than the widget), a cursor that moves across the blocks,
and the exact Hopf curve rasterised over them; once computed on request, the fold of
cycles too.

Unlike the plotext rendering of ``slopetui show``, every block here maps back to runs,
so the cursor can open the run under it.

How it is laid out (``grid_view``): a lattice that fits at one run per character is
drawn in markers, in colour; a larger one, with colour, in half blocks, two rows of runs
per character (``slopetui.plots.lattice_cells``), where the Hopf curve, the fold of
cycles and the cursor are drawn as blocks of their own colours (the line under the grid
names the run under the cursor); without colour (NO_COLOR) in markers, a block of runs
per character. A click puts the cursor on the block clicked. ``z`` switches to full
resolution, one run per block, the view following the cursor, and back; on a lattice
whose every run has its own cell already it says so (nothing would change).

An adaptive sweep is drawn like any other: an inferred run in its regime's marker and
colour, dimmed in markers (a block is dimmed when all its runs are inferred; half blocks
cannot dim a background, and leave them undimmed), and the legend counts computed and
inferred runs. Lattice points without a run yet (levels to come) are pending.

Runs that failed or were cancelled are drawn in their own style (``cell_label``, from
slopetui.plots.regime_colors.run_key), never as pending: they will not finish. In a block
of several runs they count like a regime: the block shows its most common label, and the
legend counts every run.

A 10,000-run sweep is a few thousand cells: drawn cell by cell, each with its own style,
it took 55 to 120 ms a time at 120 x 40, on every refresh and every return to the
screen. Now the text is drawn once per data, size, cursor and focus and kept, the blocks'
labels and the curves' blocks once per data and layout, and neighbouring cells of one
style are one run of text: 8 ms a draw.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from rich.style import Style
from rich.text import Text
from textual import events
from textual.binding import Binding
from textual.message import Message
from textual.reactive import reactive
from textual.widget import Widget

from slopetui.display_text import terminal_safe
from slopetui.plots.lattice_cells import all_in_blocks, block_labels, half_blocks
from slopetui.plots.regime_colors import (
    BLOCK_COLORS,
    BLOCK_CURSOR,
    BLOCK_FOLD,
    BLOCK_HOPF,
    CANCELLED,
    FAILED,
    FOLD_LABEL,
    FOLD_MARKER,
    LEGEND_ORDER,
    PENDING,
    REGIME_STYLES,
)
from slopetui.tui.messages import RunChosen, RunMarked
from slopetui.tui.widgets.grid_data import GridData, cell_label, curve_blocks
from slopetui.tui.widgets.grid_view import GridView, place

__all__ = ["FOOTER_ROWS", "GridData", "PhaseGrid", "cell_label"]

#: plotext colour names (slopetui.plots) as Rich colours; "orange" is ANSI 3 there too,
#: "blue+" ANSI 12, and "default" the terminal's foreground (failed runs).
RICH_COLOR = {"cyan": "cyan", "green": "green", "magenta": "magenta", "orange": "yellow",
              "red": "red", "blue+": "bright_blue", "gray": "bright_black",
              "default": "default"}
HOPF_STYLE = Style(bgcolor="grey30")
INFERRED_STYLE = Style(dim=True)
CURSOR_FOCUSED = Style(reverse=True, bold=True)
CURSOR_BLURRED = Style(underline=True, bold=True)
LABEL_WIDTH = 8  # y tick labels
#: Rows under the grid: x tick labels (ending in the axis name), legend, the cursor's run
#: (which names both parameters); an adaptive sweep adds its computed/inferred counts, full
#: resolution the part of the lattice in view.
FOOTER_ROWS = 3
#: Marker and style of each lattice code (the index in LEGEND_ORDER).
MARKERS: list[tuple[str, Style]] = [
    (REGIME_STYLES[key].marker, Style(color=RICH_COLOR.get(REGIME_STYLES[key].color, "default")))
    for key in LEGEND_ORDER]
#: Colour of each lattice code in half blocks.
COLOURS: list[str] = [BLOCK_COLORS[key] for key in LEGEND_ORDER]


class PhaseGrid(Widget, can_focus=True):
    """Arrows move the cursor; enter opens the run under it (posts ``RunChosen``); z
    switches between the whole lattice and full resolution (posts ``Zoomed``)."""

    DEFAULT_CSS = """
    PhaseGrid { width: 1fr; height: 1fr; min-height: 10; }
    PhaseGrid:focus { background: $boost; }
    """
    BINDINGS = [
        Binding("left", "move(-1, 0)", "←", show=False),
        Binding("right", "move(1, 0)", "→", show=False),
        Binding("up", "move(0, 1)", "↑", show=False),
        Binding("down", "move(0, -1)", "↓", show=False),
        # out of the footer: the cursor line under the grid says "enter opens it"
        Binding("enter", "choose", "Open run", id="grid.open", show=False),
        Binding("m", "mark", "Mark", id="grid.mark", show=False),
        Binding("z", "zoom", "Full resolution", id="grid.zoom", show=False,
                tooltip="One run per cell, the view following the cursor (z again: the "
                        "whole diagram)"),
    ]

    cursor: reactive[tuple[int, int]] = reactive((0, 0))
    #: Full resolution (one run per block, grid_view), or the whole lattice in view.
    full: reactive[bool] = reactive(False)

    @dataclass
    class Zoomed(Message):
        """The grid went to full resolution (``full``) or back to the whole lattice."""

        full: bool

    def __init__(self, *, id: str | None = None) -> None:
        super().__init__(id=id)
        self.data: GridData | None = None
        #: The first block in view at full resolution (grid_view.place moves it).
        self._origin = (0, 0)
        #: Bumped by set_data: what the caches below are drawn from.
        self._version = 0
        #: name -> (key, value, what the key's ids refer to: kept alive with it)
        self._cache: dict[str, tuple[Any, Any, Any]] = {}

    # --- data -----------------------------------------------------------------------
    def set_data(self, data: GridData | None) -> None:
        same_grid = (self.data is not None and data is not None
                     and (self.data.x_param, self.data.y_param, len(self.data.xs),
                          len(self.data.ys)) == (data.x_param, data.y_param, len(data.xs),
                                                 len(data.ys)))
        self.data = data
        self._version += 1
        if not same_grid:
            self.cursor = (0, 0)
            self._origin = (0, 0)
        self.refresh()

    def _cached(self, name: str, key: Any, make: Callable[[], Any], keep: Any = None) -> Any:
        hit = self._cache.get(name)
        if hit is not None and hit[0] == key:
            return hit[1]
        value = make()
        self._cache[name] = (key, value, keep)
        return value

    # --- geometry --------------------------------------------------------------------
    @property
    def colour(self) -> bool:
        """Colours are shown (not NO_COLOR): half blocks can be read."""
        return not self.app.no_color

    def view(self) -> GridView | None:
        """Where the blocks go at the current size, mode and cursor (grid_view)."""
        if self.data is None:
            return None
        d = self.data
        view = place(len(d.xs), len(d.ys), self.size.width - LABEL_WIDTH - 1,
                     self.size.height - FOOTER_ROWS - int(d.adaptive) - int(self.full),
                     colour=self.colour, full=self.full, cursor=self.cursor,
                     origin=self._origin)
        self._origin = (view.col0, view.row0)
        return view

    def _center_run(self, col: int, row: int, view: GridView) -> tuple[int, int]:
        assert self.data is not None
        return (min(col * view.sx + view.sx // 2, len(self.data.xs) - 1),
                min(row * view.sy + view.sy // 2, len(self.data.ys) - 1))

    def _curve(self, name: str, curve: tuple[np.ndarray, np.ndarray] | None,
               view: GridView, *, join: bool) -> set[tuple[int, int]]:
        """The blocks a curve passes through, kept while the curve (the same object: a
        sweep's spec never changes), the axes and the blocks are the same."""
        d = self.data
        assert d is not None
        key = (id(curve), len(d.xs), len(d.ys), float(d.xs[0]), float(d.xs[-1]),
               float(d.ys[0]), float(d.ys[-1]), d.x_log, d.y_log, view.sx, view.sy)
        return self._cached(name, key, lambda: curve_blocks(d, curve, view.sx, view.sy,
                                                            join=join), keep=curve)

    # --- the cursor --------------------------------------------------------------------
    def action_move(self, dx: int, dy: int) -> None:
        view = self.view()
        if view is None:
            return
        c, r = view.clamp(*self.cursor)
        self.cursor = view.clamp(c + dx, r + dy)

    def cursor_run(self) -> tuple[int, float, float, str | None] | None:
        """(run id, x, y, label) of the run at the centre of the cursor's block: its
        regime, "failed" or "cancelled", None while pending (GridData.runs)."""
        view = self.view()
        if view is None or self.data is None:
            return None
        ix, iy = self._center_run(*view.clamp(*self.cursor), view)
        if (ix, iy) not in self.data.runs:
            return None
        run_id, regime = self.data.runs[(ix, iy)]
        return run_id, float(self.data.xs[ix]), float(self.data.ys[iy]), regime

    def on_click(self, event: events.Click) -> None:
        """A click on a block puts the cursor there: enter then opens the run the user
        pointed at, not the one the cursor was left on. In half blocks a line holds two
        block rows; the click takes the lower (the arrows reach the upper)."""
        view = self.view()
        col = (event.x - LABEL_WIDTH) // max(view.cell_w, 1) if view is not None else -1
        if view is None or not (0 <= col < view.view_cols and 0 <= event.y < view.text_rows):
            return
        row = (self._lower_row(view, event.y) if view.half
               else view.row0 + view.view_rows - 1 - event.y)
        self.cursor = view.clamp(view.col0 + col, max(row, view.row0))

    def action_choose(self) -> None:
        found = self.cursor_run()
        if found is not None:
            self.post_message(RunChosen(found[0]))

    def action_mark(self) -> None:
        found = self.cursor_run()
        if found is not None:
            self.post_message(RunMarked(found[0]))

    def action_zoom(self) -> None:
        """Full resolution, or the whole lattice again; the cursor stays on its run. A
        lattice whose every run has a cell of its own already would look the same at full
        resolution (only the sweep list would go): it says so instead."""
        view = self.view()
        if view is None:
            return
        if not self.full and view.sx == view.sy == 1 and self.data is not None:
            self.notify(f"every run of this {len(self.data.xs)} x {len(self.data.ys)} lattice "
                        "has its own cell already: z zooms in on a lattice drawn in blocks of "
                        "several runs", title="Full resolution")
            return
        ix, iy = self._center_run(*view.clamp(*self.cursor), view)
        self.full = not self.full
        view = self.view()
        assert view is not None
        self.cursor = view.clamp(ix // view.sx, iy // view.sy)
        self.post_message(self.Zoomed(self.full))

    # --- rendering ------------------------------------------------------------------------
    def render(self) -> Text:
        view = self.view()
        if view is None or self.data is None:
            return Text("no sweep selected")
        key = (self._version, self.size, view, self.cursor, self.has_focus, self.colour)
        return self._cached("text", key, lambda: self._draw(view))

    def _draw(self, view: GridView) -> Text:
        d = self.data
        assert d is not None
        width = self.size.width
        labels = self._cached("labels", (self._version, view.sx, view.sy),
                              lambda: block_labels(d.codes, view.sx, view.sy))
        dimmed = (self._cached("dimmed", (self._version, view.sx, view.sy),
                               lambda: all_in_blocks(d.inferred_mask, view.sx, view.sy))
                  if d.inferred else None)
        hopf = self._curve("hopf", d.hopf, view, join=True)
        folds = self._curve("fold", d.fold, view, join=False)
        cursor = view.clamp(*self.cursor)
        rows = (self._half_rows(view, labels, hopf, folds, cursor) if view.half else
                self._marker_rows(view, labels, dimmed, hopf, folds, cursor))
        out = Text(no_wrap=True, overflow="crop")
        every = max(1, len(rows) // 6)
        for t, cells in enumerate(rows):
            if t == 0:  # the top row names the y axis
                out.append(f"{d.y_param} ↑"[:LABEL_WIDTH - 1].rjust(LABEL_WIDTH - 1) + "│")
            elif (len(rows) - 1 - t) % every == 0:
                iy = self._center_run(0, self._lower_row(view, t), view)[1]
                out.append(f"{d.ys[iy]:.4g}".rjust(LABEL_WIDTH - 1) + "┤")
            else:
                out.append(" " * (LABEL_WIDTH - 1) + "│")
            for text, style in cells:
                out.append(text, style)
            out.append("\n")
        out.append(self._x_ticks(view)[:width] + "\n")
        self._legend(out, view, width)
        out.append("\n")
        if d.adaptive:  # a line of its own: the legend line has no room left at 80 columns
            # computed: done (as sweep_diagram.adaptive_notes); a failed run gave no result
            computed = sum(r not in (None, FAILED, CANCELLED) and p not in d.inferred
                           for p, (_, r) in d.runs.items())
            out.append(f"adaptive: {computed} computed, ")
            if view.half:
                out.append(f"{len(d.inferred)} inferred")
            else:
                out.append(f"{len(d.inferred)} inferred (dim)", INFERRED_STYLE)
            if d.n_unqueued:
                out.append(f", {d.n_unqueued} not queued yet")
            out.append("\n")
        if self.full:
            out.append(self._in_view(view) + "\n")
        found = self.cursor_run()
        if found is not None:
            run_id, x, y, regime = found
            cell = self._center_run(*cursor, view)
            how = ", inferred" if cell in d.inferred else ""
            label = terminal_safe(regime or "pending")  # stored text
            which = f" [{terminal_safe(d.notes[cell])}]" if cell in d.notes else ""
            out.append(f"{d.x_param} = {x:.5g}, {d.y_param} = {y:.5g}: "
                       f"{label}{how}{which} (run {run_id}; enter opens it)",
                       Style(bold=True))
        return out

    @staticmethod
    def _lower_row(view: GridView, t: int) -> int:
        """The block row drawn in the lower half of text row t (the row, in markers)."""
        if not view.half:
            return view.row0 + view.view_rows - 1 - t
        pad = view.view_rows % 2  # an odd count leaves the top half of the first line empty
        return view.row0 + view.view_rows - 1 - (2 * t + 1 - pad)

    def _marker_rows(self, view: GridView, labels: np.ndarray, dimmed: np.ndarray | None,
                     hopf: set[tuple[int, int]], folds: set[tuple[int, int]],
                     cursor: tuple[int, int]) -> list[list[tuple[str, Style]]]:
        """One marker per block, runs of one style merged."""
        cursor_style = CURSOR_FOCUSED if self.has_focus else CURSOR_BLURRED
        out = []
        for t in range(view.view_rows):
            row = view.row0 + view.view_rows - 1 - t
            cells: list[tuple[str, Style]] = []
            for col in range(view.col0, view.col0 + view.view_cols):
                marker, style = MARKERS[labels[row, col]]
                if dimmed is not None and dimmed[row, col]:
                    style = style + INFERRED_STYLE
                if (col, row) in hopf:
                    style = style + HOPF_STYLE
                if (col, row) == cursor:
                    style = style + cursor_style
                text = marker.center(view.cell_w)
                if (col, row) in folds:  # beside the regime's marker when there is room
                    text = FOLD_MARKER + (marker.center(view.cell_w - 1) if view.cell_w > 1
                                          else "")
                if cells and cells[-1][1] == style:
                    cells[-1] = (cells[-1][0] + text, style)
                else:
                    cells.append((text, style))
            out.append(cells)
        return out

    def _half_rows(self, view: GridView, labels: np.ndarray, hopf: set[tuple[int, int]],
                   folds: set[tuple[int, int]], cursor: tuple[int, int]
                   ) -> list[list[tuple[str, Style]]]:
        """Two block rows per line in half blocks; the overlays as blocks of their own
        colours (regime_colors.BLOCK_*), the cursor's on top."""
        pixels: list[list[str | None]] = []
        for p in range(view.view_rows):
            row = view.row0 + view.view_rows - 1 - p
            line: list[str | None] = []
            for col in range(view.col0, view.col0 + view.view_cols):
                colour = COLOURS[labels[row, col]]
                if (col, row) == cursor:
                    colour = BLOCK_CURSOR
                elif (col, row) in folds:
                    colour = BLOCK_FOLD
                elif (col, row) in hopf:
                    colour = BLOCK_HOPF
                line.extend([colour] * view.cell_w)
            pixels.append(line)
        styles: dict[tuple[str | None, str | None], Style] = {}
        return [[(text, styles.setdefault((fg, bg), Style(color=fg, bgcolor=bg)))
                 for text, fg, bg in runs] for runs in half_blocks(pixels)]

    def _legend(self, out: Text, view: GridView, width: int) -> None:
        d = self.data
        assert d is not None
        counts = Counter(r or PENDING for _, r in d.runs.values())
        counts[PENDING] += d.n_unqueued
        for key in LEGEND_ORDER:
            if counts.get(key):
                if view.half:
                    out.append("█", Style(color=BLOCK_COLORS[key]))
                else:
                    out.append(*MARKERS[LEGEND_ORDER.index(key)])
                out.append(f" {key} ({counts[key]})  ")
        if d.hopf is not None:
            if view.half:
                out.append(" █", Style(color=BLOCK_HOPF))
            else:
                out.append("  ", HOPF_STYLE)
            out.append(" Hopf (exact)")
        if d.fold is not None and len(d.fold[0]):
            used = len(out.plain) - out.plain.rfind("\n") - 1
            mark = "█" if view.half else FOLD_MARKER
            style = Style(color=BLOCK_FOLD) if view.half else Style()
            label = f" {FOLD_LABEL}" if used + len(FOLD_LABEL) + 4 <= width else " fold"
            out.append("  ")
            out.append(mark, style)
            out.append(label)

    def _in_view(self, view: GridView) -> str:
        """At full resolution: which runs are in view, and how to see them all."""
        d = self.data
        assert d is not None
        nx, ny = len(d.xs), len(d.ys)
        return (f"z: whole diagram; in view {d.x_param} {view.col0 + 1}-"
                f"{view.col0 + view.view_cols} of {nx}, {d.y_param} {view.row0 + 1}-"
                f"{view.row0 + view.view_rows} of {ny}")

    def _x_ticks(self, view: GridView) -> str:
        assert self.data is not None
        line = [" "] * (LABEL_WIDTH + view.view_cols * view.cell_w + 8)
        line[LABEL_WIDTH - 1] = "└"
        every = max(1, 10 // view.cell_w)
        for i in range(0, view.view_cols, every):
            ix = self._center_run(view.col0 + i, 0, view)[0]
            text = f"{self.data.xs[ix]:.4g}"
            start = LABEL_WIDTH + i * view.cell_w
            if start + len(text) <= len(line):
                line[start:start + len(text)] = list(text)
        return "".join(line).rstrip() + f"  → {self.data.x_param}"

    def watch_cursor(self) -> None:
        self.refresh()

    def watch_full(self) -> None:
        self.refresh()

    def on_focus(self) -> None:
        self.refresh()

    def on_blur(self) -> None:
        self.refresh()
