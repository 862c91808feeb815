"""The live phase diagram of a 2-D sweep: one terminal cell per run (or per block of
runs when the sweep is larger than the widget), a cursor that moves across the cells,
and the exact Hopf curve rasterised over them; once computed on request, the fold of
cycles too (a '•' before the regime's marker in the cells it passes through).

Unlike the plotext rendering of ``slopetui show``, every cell here maps back to runs,
so the cursor can open the run under it.

An adaptive sweep is drawn like any other: an inferred run in its regime's marker and
colour, dimmed (a display cell is dimmed when all its runs are inferred), and the legend
counts computed and inferred runs. Lattice points without a run yet (levels to come)
are pending.

Runs that failed or were cancelled are drawn in their own style (``cell_label``, from
slopetui.plots.regime_colors.run_key), never as pending: they will not finish. In a block
of several runs they count like a regime: the block shows its most common label, and the
legend counts every run.
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass, field

import numpy as np
from rich.style import Style
from rich.text import Text
from textual.binding import Binding
from textual.reactive import reactive
from textual.widget import Widget

from slopetui.display_text import terminal_safe
from slopetui.plots.regime_colors import (
    CANCELLED,
    FAILED,
    FOLD_LABEL,
    FOLD_MARKER,
    LEGEND_ORDER,
    PENDING,
    REGIME_STYLES,
    run_key,
)
from slopetui.tui.messages import RunChosen, RunMarked

#: plotext colour names (slopetui.plots) as Rich colours; "orange" is ANSI 3 there too,
#: "blue+" ANSI 12, and "default" the terminal's foreground (failed runs).
RICH_COLOR = {"cyan": "cyan", "green": "green", "magenta": "magenta", "orange": "yellow",
              "red": "red", "blue+": "bright_blue", "gray": "bright_black",
              "default": "default"}
HOPF_STYLE = Style(bgcolor="grey30")
INFERRED_STYLE = Style(dim=True)
LABEL_WIDTH = 8  # y tick labels
#: Rows under the grid: x tick labels (ending in the axis name), legend, the cursor's run
#: (which names both parameters); an adaptive sweep adds its computed/inferred counts.
FOOTER_ROWS = 3


@dataclass
class GridData:
    """A sweep's grid: axis values and, per (ix, iy), the run id and its label
    (``cell_label``: a regime, DEPENDS, FAILED or CANCELLED; None while not finished)."""

    x_param: str
    y_param: str
    xs: np.ndarray
    ys: np.ndarray
    x_log: bool
    y_log: bool
    runs: dict[tuple[int, int], tuple[int, str | None]] = field(default_factory=dict)
    hopf: tuple[np.ndarray, np.ndarray] | None = None
    #: Adaptive sweeps: the grid points whose run was inferred, not computed.
    inferred: frozenset[tuple[int, int]] = frozenset()
    adaptive: bool = False
    #: The fold-of-cycles curve (k, tau) of a (k, tau) plane, once computed.
    fold: tuple[np.ndarray, np.ndarray] | None = None
    #: A sweep of several initial conditions: per cell, what each one ended in.
    notes: dict[tuple[int, int], str] = field(default_factory=dict)

    @property
    def n_unqueued(self) -> int:
        """Grid points without a run (an adaptive sweep's levels still to come)."""
        return len(self.xs) * len(self.ys) - len(self.runs)


def cell_label(regime: str | None, status: str | None) -> str | None:
    """A run's label in GridData.runs: its style key (run_key), None while pending (queued
    or running), so that failed and cancelled runs are not drawn as runs to come."""
    key = run_key(regime, status)
    return None if key == PENDING else key


def _style(regime: str | None) -> tuple[str, Style]:
    key = regime or PENDING
    s = REGIME_STYLES[key]
    return s.marker, Style(color=RICH_COLOR.get(s.color, "default"))


def _axis_position(values: np.ndarray, log: bool, v: float) -> float:
    """Fractional grid index of the value v on an axis of the given values."""
    if len(values) == 1:
        return 0.0
    lo, hi = (np.log(values[0]), np.log(values[-1])) if log else (values[0], values[-1])
    if log:
        if v <= 0:
            return math.nan
        v = math.log(v)
    return (v - lo) / (hi - lo) * (len(values) - 1)


class PhaseGrid(Widget, can_focus=True):
    """Arrows move the cursor; enter opens the run under it (posts ``RunChosen``)."""

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
    ]

    cursor: reactive[tuple[int, int]] = reactive((0, 0))

    def __init__(self, *, id: str | None = None) -> None:
        super().__init__(id=id)
        self.data: GridData | None = None

    # --- data -----------------------------------------------------------------------
    def set_data(self, data: GridData | None) -> None:
        same_grid = (self.data is not None and data is not None
                     and (self.data.x_param, self.data.y_param, len(self.data.xs),
                          len(self.data.ys)) == (data.x_param, data.y_param, len(data.xs),
                                                 len(data.ys)))
        self.data = data
        if not same_grid:
            self.cursor = (0, 0)
        self.refresh()

    # --- geometry: display cells, each covering a block of runs -----------------------
    def _layout(self) -> tuple[int, int, int, int, int] | None:
        """(cell width, x stride, y stride, columns, rows) for the current size."""
        if self.data is None:
            return None
        width = max(self.size.width - LABEL_WIDTH - 1, 1)
        height = max(self.size.height - FOOTER_ROWS - int(self.data.adaptive), 1)
        nx, ny = len(self.data.xs), len(self.data.ys)
        sx, sy = math.ceil(nx / width), math.ceil(ny / height)
        cols, rows = math.ceil(nx / sx), math.ceil(ny / sy)
        cell_w = max(1, min(3, width // cols))
        return cell_w, sx, sy, cols, rows

    def _block(self, col: int, row: int, sx: int, sy: int) -> list[tuple[int, str | None]]:
        assert self.data is not None
        return [self.data.runs[(ix, iy)]
                for ix in range(col * sx, min((col + 1) * sx, len(self.data.xs)))
                for iy in range(row * sy, min((row + 1) * sy, len(self.data.ys)))
                if (ix, iy) in self.data.runs]

    def _all_inferred(self, col: int, row: int, sx: int, sy: int) -> bool:
        assert self.data is not None
        if not self.data.inferred:
            return False
        return all((ix, iy) in self.data.inferred
                   for ix in range(col * sx, min((col + 1) * sx, len(self.data.xs)))
                   for iy in range(row * sy, min((row + 1) * sy, len(self.data.ys))))

    def _label(self, block: list[tuple[int, str | None]]) -> str | None:
        done = Counter(r for _, r in block if r is not None)
        return done.most_common(1)[0][0] if done else None

    def _center_run(self, col: int, row: int, sx: int, sy: int) -> tuple[int, int]:
        assert self.data is not None
        return (min(col * sx + sx // 2, len(self.data.xs) - 1),
                min(row * sy + sy // 2, len(self.data.ys) - 1))

    def _curve_cells(self, curve: tuple[np.ndarray, np.ndarray] | None, sx: int, sy: int,
                     *, join: bool = True) -> set[tuple[int, int]]:
        """Display cells a curve passes through (the exact Hopf curve); with ``join``
        False only the cells of its points (the fold of cycles, one point per tau)."""
        assert self.data is not None
        d = self.data
        if curve is None or len(curve[0]) == 0:
            return set()
        fx = np.array([_axis_position(d.xs, d.x_log, float(v)) for v in curve[0]])
        fy = np.array([_axis_position(d.ys, d.y_log, float(v)) for v in curve[1]])
        if not join:
            return {(round(x) // sx, round(y) // sy) for x, y in zip(fx, fy, strict=True)
                    if np.isfinite(x) and np.isfinite(y) and -0.5 <= x <= len(d.xs) - 0.5
                    and -0.5 <= y <= len(d.ys) - 0.5}
        cells = set()
        for i in range(len(fx) - 1):  # interpolate, so that steep stretches stay joined
            steps = int(max(abs(fx[i + 1] - fx[i]) / sx, abs(fy[i + 1] - fy[i]) / sy, 1) * 2)
            for s in np.linspace(0.0, 1.0, steps + 1):
                x = fx[i] + s * (fx[i + 1] - fx[i])
                y = fy[i] + s * (fy[i + 1] - fy[i])
                if np.isfinite(x) and np.isfinite(y) and -0.5 <= x <= len(d.xs) - 0.5 \
                        and -0.5 <= y <= len(d.ys) - 0.5:
                    cells.add((round(x) // sx, round(y) // sy))
        return cells

    # --- the cursor --------------------------------------------------------------------
    def action_move(self, dx: int, dy: int) -> None:
        layout = self._layout()
        if layout is None:
            return
        _, _, _, cols, rows = layout
        c, r = self.cursor
        self.cursor = (min(max(c + dx, 0), cols - 1), min(max(r + dy, 0), rows - 1))

    def cursor_run(self) -> tuple[int, float, float, str | None] | None:
        """(run id, x, y, label) of the run at the centre of the cursor's cell: its regime,
        "failed" or "cancelled", None while pending (GridData.runs)."""
        layout = self._layout()
        if layout is None or self.data is None:
            return None
        _, sx, sy, cols, rows = layout
        c, r = min(self.cursor[0], cols - 1), min(self.cursor[1], rows - 1)
        ix, iy = self._center_run(c, r, sx, sy)
        if (ix, iy) not in self.data.runs:
            return None
        run_id, regime = self.data.runs[(ix, iy)]
        return run_id, float(self.data.xs[ix]), float(self.data.ys[iy]), regime

    def action_choose(self) -> None:
        found = self.cursor_run()
        if found is not None:
            self.post_message(RunChosen(found[0]))

    def action_mark(self) -> None:
        found = self.cursor_run()
        if found is not None:
            self.post_message(RunMarked(found[0]))

    # --- rendering ------------------------------------------------------------------------
    def render(self) -> Text:
        width = self.size.width
        layout = self._layout()
        if layout is None or self.data is None:
            return Text("no sweep selected")
        d = self.data
        cell_w, sx, sy, cols, rows = layout
        hopf = self._curve_cells(d.hopf, sx, sy)
        folds = self._curve_cells(d.fold, sx, sy, join=False)
        cursor = (min(self.cursor[0], cols - 1), min(self.cursor[1], rows - 1))
        out = Text(no_wrap=True, overflow="crop")
        label_every = max(1, rows // 6)
        for row_top in range(rows):
            row = rows - 1 - row_top  # larger y on top
            iy = self._center_run(0, row, sx, sy)[1]
            if row_top == 0:  # the top row names the y axis
                out.append(f"{d.y_param} ↑"[:LABEL_WIDTH - 1].rjust(LABEL_WIDTH - 1) + "│")
            elif row % label_every == 0 or row == rows - 1:
                out.append(f"{d.ys[iy]:.4g}".rjust(LABEL_WIDTH - 1) + "┤")
            else:
                out.append(" " * (LABEL_WIDTH - 1) + "│")
            for col in range(cols):
                marker, style = _style(self._label(self._block(col, row, sx, sy)))
                if self._all_inferred(col, row, sx, sy):
                    style = style + INFERRED_STYLE
                if (col, row) in hopf:
                    style = style + HOPF_STYLE
                if (col, row) == cursor:
                    style = style + (Style(reverse=True, bold=True) if self.has_focus
                                     else Style(underline=True, bold=True))
                text = marker.center(cell_w)
                if (col, row) in folds:  # beside the regime's marker when there is room
                    text = FOLD_MARKER + (marker.center(cell_w - 1) if cell_w > 1 else "")
                out.append(text, style)
            out.append("\n")
        out.append(self._x_ticks(cols, cell_w, sx)[:width] + "\n")
        counts = Counter(r or PENDING for _, r in d.runs.values())
        counts[PENDING] += d.n_unqueued
        for key in LEGEND_ORDER:
            if counts.get(key):
                marker, style = _style(None if key == PENDING else key)
                out.append(marker, style)
                out.append(f" {key} ({counts[key]})  ")
        if d.hopf is not None:
            out.append("  ", HOPF_STYLE)
            out.append(" Hopf (exact)")
        if d.fold is not None and len(d.fold[0]):
            used = len(out.plain) - out.plain.rfind("\n") - 1
            label = f"  {FOLD_MARKER} {FOLD_LABEL}"
            out.append(label if used + len(label) <= width else f"  {FOLD_MARKER} fold")
        out.append("\n")
        if d.adaptive:  # a line of its own: the legend line has no room left at 80 columns
            # computed: done (as sweep_diagram.adaptive_notes); a failed run gave no result
            computed = sum(r not in (None, FAILED, CANCELLED) and p not in d.inferred
                           for p, (_, r) in d.runs.items())
            out.append(f"adaptive: {computed} computed, ")
            out.append(f"{len(d.inferred)} inferred (dim)", INFERRED_STYLE)
            if d.n_unqueued:
                out.append(f", {d.n_unqueued} not queued yet")
            out.append("\n")
        found = self.cursor_run()
        if found is not None:
            run_id, x, y, regime = found
            cell = self._center_run(*cursor, sx, sy)
            how = ", inferred" if cell in d.inferred else ""
            label = terminal_safe(regime or "pending")  # stored text
            which = f" [{terminal_safe(d.notes[cell])}]" if cell in d.notes else ""
            out.append(f"{d.x_param} = {x:.5g}, {d.y_param} = {y:.5g}: "
                       f"{label}{how}{which} (run {run_id}; enter opens it)",
                       Style(bold=True))
        return out

    def _x_ticks(self, cols: int, cell_w: int, sx: int) -> str:
        assert self.data is not None
        line = [" "] * (LABEL_WIDTH + cols * cell_w + 8)
        line[LABEL_WIDTH - 1] = "└"
        every = max(1, 10 // cell_w)
        for col in range(0, cols, every):
            ix = self._center_run(col, 0, sx, 1)[0]
            text = f"{self.data.xs[ix]:.4g}"
            start = LABEL_WIDTH + col * cell_w
            if start + len(text) <= len(line):
                line[start:start + len(text)] = list(text)
        return "".join(line).rstrip() + f"  → {self.data.x_param}"

    def watch_cursor(self) -> None:
        self.refresh()

    def on_focus(self) -> None:
        self.refresh()

    def on_blur(self) -> None:
        self.refresh()
