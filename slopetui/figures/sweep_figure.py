"""A sweep's diagram as a publication figure: the file counterpart of
slopetui.plots.sweep_diagram, drawing the same things.

A 2-D sweep gives its **phase diagram**: one filled cell per lattice point, coloured by
regime, the exact Hopf curve over it (solid black) and the fold of cycles where given
(dashed). Runs that failed or were cancelled are cells of their own colour, not pending
ones (slopetui.plots.regime_colors.run_key). A sweep with two or more initial conditions
draws their map (each cell's common regime, "depends", or failed, cancelled or pending:
slopetui.sweeps.initial_dependence.drawn); lattice points without a run yet (an
adaptive sweep's levels to come) are drawn as pending, and an adaptive sweep says in the
legend how many runs were computed and how many inferred (the terminal's line,
slopetui.plots.sweep_diagram.adaptive_notes).

A 1-D sweep gives its **bifurcation diagram** (the paper's Fig. 4A): the peak clusters of
m_y of each run against the parameter, coloured by the run's regime; a sliding run comes
with its window mean of m_y (slopetui.sweeps.diagram.load_diagram). Every initial
condition's runs are overlaid. Failed and cancelled runs have no peaks: the legend counts
them.

Decisions:

* **Cells, not points.** A filled lattice reads as regions at any size, as the paper's
  figures do. Edges are midpoints between lattice values, geometric on a log-spaced axis,
  which is then drawn on a log scale (slopetui.figures.lattice).
* **The cells are rasterised** (RASTER_DPI in a PDF or SVG), the axes, labels and curves
  stay vector. Measured on the 100 x 100 diagram of tests/unit/test_figures.py: the PDF
  is 20 kB rasterised against 129 kB with every cell a vector path (SVG: 46 kB against
  1.9 MB); on a 300 x 300 lattice 23 kB against 1.7 MB (SVG: 63 kB against 17 MB).
  Cells are drawn without anti-aliasing, so neighbours of one colour leave no seams.
* **Markers of a bifurcation diagram** are rasterised above RASTER_POINTS points.
  Measured on 200 runs, half of them with their peaks spread over a chaotic band: as
  vectors a PDF grows by ~8 bytes a marker (2,000 points 38 kB, 10,000 102 kB, 50,000
  421 kB, 100,000 821 kB, and viewers slow down), while the raster stays 130 kB or less
  and shrinks as the band fills (10,000 points 128 kB, 25,000 89 kB, 50,000 42 kB).
  They cross near 10,000; below it vectors are no larger and stay sharp when zoomed. The
  most numerous regime is drawn first so the rare ones stay visible on top (as in the
  terminal).
* **Counts in the legend**: runs per regime (cells, for a phase diagram), as
  "oscillatory (1,234)", in the terminal's legend order.

The tables beside the figure: a phase diagram's "points", one row per drawn cell (with
several initial conditions the run id and λmax are the first condition's, the regime
and status the cell's, as drawn), and "curves", the Hopf and fold samples, when there
are any; a bifurcation diagram's "peaks", one row per peak. A measurement that does not exist (an
inferred or unfinished run's λmax) is an empty cell, one that is undefined nan.

**The points' regime column holds regimes only** (and "depends", a cell's verdict): a
run without one (queued, running, failed, cancelled) leaves it empty, and the **status**
column says why: the run's status (done, queued, running, failed, cancelled), empty for
a lattice point without a run yet. A label is a claim about the model: "failed" in a
column of regimes would read as one, and a table filtered on regime would mix the runs
that gave no answer with those that did. The figure's colours are the run_key's (the
legend's keys); the table keeps what was computed apart from why nothing was.
"""

from __future__ import annotations

import textwrap
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from slopetui.figures.canvas import empty_panel, log_scale, new_figure, set_title
from slopetui.figures.labels import PEAKS_LABEL, axis_label
from slopetui.figures.lattice import cell_edges
from slopetui.figures.output import Drawing, Table
from slopetui.figures.style import FOLD_LABEL, FOLD_STYLE, HOPF_LABEL, HOPF_STYLE, REGIME_COLORS
from slopetui.plots.regime_colors import LEGEND_ORDER, PENDING, regime_counts, run_key
from slopetui.plots.sweep_diagram import adaptive_notes
from slopetui.sweeps.initial_dependence import drawn

if TYPE_CHECKING:
    from matplotlib.artist import Artist
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from slopetui.sweeps.diagram import SweepDiagram
    from slopetui.sweeps.hopf_plane import Curve

__all__ = ["DIAGRAM_SIZE", "RASTER_POINTS", "sweep_drawing"]

#: Size of a diagram figure (inches): matplotlib's default, a single column of a journal
#: page at a legible scale.
DIAGRAM_SIZE: tuple[float, float] = (6.4, 4.8)
#: A bifurcation diagram's markers are rasterised above this many points (module docstring).
RASTER_POINTS = 10_000
#: Marker area of a bifurcation diagram's peaks (points²): about 3 pt across. At 2 pt
#: the 43 runs of Fig. 4A were specks in docs/figures/fig4a.png; at 3 pt neighbouring
#: runs of a 200-run sweep (0.025 in apart on a 5 in axis) still stay separate.
MARKER_AREA = 9.0
#: A legend note wraps at this many characters (the legend sits right of the axes).
NOTE_WRAP = 24


def sweep_drawing(diagram: SweepDiagram, *, hopf: Curve | None, fold: Curve | None = None,
                  title: str | None = None) -> Drawing:
    """The sweep's phase diagram (2-D) or bifurcation diagram (1-D), with its data tables.

    ``hopf`` is the exact Hopf curve of the plane (slopetui.sweeps.diagram.plane_hopf),
    ``fold`` a fold-of-cycles curve, both as (x values, y values) in the plane's
    parameters; a 1-D sweep has neither and ignores them. ``title`` defaults to "sweep
    {id}: {name}" and is drawn as plain text (no mathtext). Raises ValueError for a run
    with a regime the classifier never produces.
    """
    if title is None:
        title = f"sweep {diagram.id}: {diagram.name}"
    if diagram.spec.y is None:
        return _bifurcation(diagram, title)
    return _phase_diagram(diagram, hopf, fold, title)


# -- phase diagram --------------------------------------------------------------------------

@dataclass(frozen=True)
class _Cell:
    run_id: int | None
    ix: int
    iy: int
    x: float
    y: float
    key: str                # the style key (run_key)
    regime: str | None      # the run's regime (or DEPENDS); None without one
    status: str | None      # the run's status; None for a lattice point without a run
    lambda_max: float | None
    inferred: bool


def _cells(diagram: SweepDiagram) -> list[_Cell]:
    """What the phase diagram draws: each run of the drawn map, then the lattice points
    without a run as pending; in lattice order (y, then x)."""
    out = []
    for r in drawn(diagram).runs:
        measured = r.status == "done" and not r.inferred
        out.append(_Cell(r.id, r.ix, r.iy, r.x, float("nan") if r.y is None else r.y,
                         run_key(r.regime, r.status), r.regime, r.status,
                         r.lambda_max if measured else None, r.inferred))
    for ix, iy, x, y in diagram.unqueued():
        out.append(_Cell(None, ix, iy, x, float("nan") if y is None else y, PENDING, None, None,
                         None, False))
    return sorted(out, key=lambda c: (c.iy, c.ix))


def _phase_diagram(diagram: SweepDiagram, hopf: Curve | None, fold: Curve | None,
                   title: str) -> Drawing:
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.patches import Patch

    spec = diagram.spec
    assert spec.y is not None
    x_axis, y_axis = spec.x, spec.y
    x_log, y_log = x_axis.spacing == "log", y_axis.spacing == "log"
    xs, ys = x_axis.values(), y_axis.values()
    cells = _cells(diagram)
    # one colour index per lattice point (LEGEND_ORDER), -1 (masked: blank) for none
    codes = np.full((len(ys), len(xs)), -1, dtype=int)
    for c in cells:
        if 0 <= c.ix < len(xs) and 0 <= c.iy < len(ys):
            codes[c.iy, c.ix] = LEGEND_ORDER.index(c.key)

    fig = new_figure(DIAGRAM_SIZE)
    ax = fig.add_subplot()
    x_edges, y_edges = cell_edges(xs, x_log), cell_edges(ys, y_log)
    n = len(LEGEND_ORDER)
    ax.pcolormesh(x_edges, y_edges, np.ma.masked_less(codes, 0),
                  cmap=ListedColormap([REGIME_COLORS[k] for k in LEGEND_ORDER]),
                  norm=BoundaryNorm(np.arange(n + 1) - 0.5, n), shading="flat",
                  rasterized=True, antialiased=False, linewidth=0)
    _set_scales(ax, x_log, y_log)
    ax.set_xlabel(axis_label(x_axis.param))
    ax.set_ylabel(axis_label(y_axis.param))
    handles: list[Artist] = [Patch(facecolor=REGIME_COLORS[key], edgecolor="none",
                                   label=f"{key} ({count:,})")
                             for key, count in regime_counts(c.key for c in cells).items()]
    limits = (min(x_edges), max(x_edges)), (min(y_edges), max(y_edges))
    for label, curve, style in ((HOPF_LABEL, hopf, HOPF_STYLE), (FOLD_LABEL, fold, FOLD_STYLE)):
        shown = _visible_curve(curve, x_log, y_log, limits)
        if shown is not None:
            (line,) = ax.plot(*shown, label=label, **style)  # type: ignore[arg-type]
            handles.append(line)
    # the curves must not widen the view beyond the lattice
    ax.set_xlim(*limits[0])
    ax.set_ylim(*limits[1])
    _legend(fig, handles, adaptive_notes(diagram))
    set_title(fig, title, ax)

    x_name, y_name = x_axis.param, y_axis.param
    points = Table("points", ("run_id", "ix", "iy", x_name, y_name, "regime", "status",
                              "lambda_max", "inferred"),
                   [(c.run_id, c.ix, c.iy, c.x, c.y, c.regime, c.status, c.lambda_max,
                     c.inferred) for c in cells])
    curve_rows: list[tuple[Any, ...]] = []
    for name, curve in (("hopf", hopf), ("fold", fold)):
        if curve is not None:
            curve_rows.extend((name, float(cx), float(cy)) for cx, cy in zip(*curve, strict=True))
    tables = [points]
    if curve_rows:
        tables.append(Table("curves", ("curve", x_name, y_name), curve_rows))
    return Drawing(fig, tuple(tables))


def _visible_curve(curve: Curve | None, x_log: bool, y_log: bool,
                   limits: tuple[tuple[float, float], tuple[float, float]]
                   ) -> tuple[np.ndarray, np.ndarray] | None:
    """The curve with the samples a log axis cannot show blanked (NaN breaks the line),
    or None when no sample falls inside the diagram."""
    if curve is None:
        return None
    x = np.asarray(curve[0], dtype=float)
    y = np.asarray(curve[1], dtype=float)
    if x.shape != y.shape:
        raise ValueError(f"a curve's x and y differ in length: {x.size}, {y.size}")
    ok = np.isfinite(x) & np.isfinite(y)
    if x_log:
        ok &= x > 0.0
    if y_log:
        ok &= y > 0.0
    (x_lo, x_hi), (y_lo, y_hi) = limits
    inside = ok & (x >= x_lo) & (x <= x_hi) & (y >= y_lo) & (y <= y_hi)
    if not inside.any():
        return None
    return np.where(ok, x, np.nan), np.where(ok, y, np.nan)


# -- bifurcation diagram --------------------------------------------------------------------

def _bifurcation(diagram: SweepDiagram, title: str) -> Drawing:
    from matplotlib.lines import Line2D

    x_axis = diagram.spec.x
    log = x_axis.spacing == "log"
    keys = [run_key(r.regime, r.status) for r in diagram.runs]
    keys += [PENDING] * len(diagram.unqueued())  # counted: they have no peaks to draw
    points: dict[str, tuple[list[float], list[float]]] = {}
    rows: list[tuple[Any, ...]] = []
    for r, key in zip(diagram.runs, keys, strict=False):
        for peak in r.peaks:
            rows.append((r.id, r.x, peak, key))
            if np.isfinite(r.x) and np.isfinite(peak) and (r.x > 0.0 or not log):
                px, py = points.setdefault(key, ([], []))
                px.append(r.x)
                py.append(peak)

    fig = new_figure(DIAGRAM_SIZE)
    ax = fig.add_subplot()
    total = sum(len(px) for px, _ in points.values())
    rasterized = total > RASTER_POINTS
    # the most numerous regime first: where markers overlap, the rarer ones stay on top
    for z, key in enumerate(sorted(points, key=lambda k: (-len(points[k][0]),
                                                          LEGEND_ORDER.index(k)))):
        px, py = points[key]
        ax.scatter(px, py, s=MARKER_AREA, color=REGIME_COLORS[key], linewidths=0,
                   rasterized=rasterized, zorder=2 + 0.01 * z)
    _set_scales(ax, log, False)
    ax.set_xlabel(axis_label(x_axis.param))
    ax.set_ylabel(PEAKS_LABEL)
    if not total:
        empty_panel(ax, f"{len(keys):,} runs, no peaks to plot yet" if keys else "no runs")
    handles: list[Artist] = [Line2D([], [], linestyle="none", marker="o", markersize=6,
                                    markeredgewidth=0, color=REGIME_COLORS[key],
                                    label=f"{key} ({count:,})")
                             for key, count in regime_counts(keys).items()]
    _legend(fig, handles, adaptive_notes(diagram))
    set_title(fig, title, ax)
    table = Table("peaks", ("run_id", x_axis.param, "peak_m_y", "regime"), rows)
    return Drawing(fig, (table,))


# -- shared ---------------------------------------------------------------------------------

def _set_scales(ax: Axes, x_log: bool, y_log: bool) -> None:
    if x_log:
        log_scale(ax, "x")
    if y_log:
        log_scale(ax, "y")


def _legend(fig: Figure, handles: list[Artist], notes: Sequence[str]) -> None:
    """The legend right of the axes (outside: it must not hide cells), notes as lines of
    text without a handle."""
    from matplotlib.patches import Rectangle

    for text in notes:  # wrapped: a long line would squeeze the axes
        handles.append(Rectangle((0, 0), 0, 0, fill=False, edgecolor="none",
                                 label=textwrap.fill(text, NOTE_WRAP)))
    if handles:
        fig.legend(handles=handles, loc="outside right upper", frameon=False, fontsize=9)
