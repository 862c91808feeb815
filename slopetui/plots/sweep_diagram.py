"""A sweep's diagram, the one render path of ``slopetui show``, the reproduction report
and the application's bifurcation view.

A 2-D sweep draws its phase diagram (one colour and marker per regime, the exact Hopf
curve of ``core.stability`` over it where the plane has one); a 1-D sweep draws its
bifurcation diagram (the peak clusters of m_y against the parameter, as in Fig. 4A).
Runs that are not finished yet are drawn as pending, runs that failed or were cancelled
as such (``regime_colors.run_key``: not as pending, they will not finish); sliding runs
of a bifurcation diagram at their mean m_y (near the fixed point m_y = 0; see
``load_diagram``). An adaptive phase diagram is drawn like any other: inferred runs in
their regime's style, lattice points of levels not queued yet as pending, and "N
computed, M inferred" in the legend.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from slopetui.display_text import terminal_safe
from slopetui.plots.bifurcation import render_bifurcation
from slopetui.plots.phase_diagram import render_phase_diagram
from slopetui.plots.regime_colors import run_key
from slopetui.sweeps.diagram import plane_hopf
from slopetui.sweeps.initial_dependence import drawn

if TYPE_CHECKING:  # slopetui.sweeps.diagram loads the store: imported where used
    from slopetui.sweeps.diagram import SweepDiagram


def render_sweep(diagram: SweepDiagram, *, width: int, height: int, color: bool,
                 hopf: bool = True, fold: tuple[np.ndarray, np.ndarray] | None = None,
                 title: str | None = None, cursor: float | None = None) -> str:
    """The sweep's phase diagram (2-D) or bifurcation diagram (1-D), ``height`` lines of
    at most ``width`` columns, ANSI-coloured when ``color``. ``hopf`` draws the exact Hopf
    curve over a phase diagram whose plane has one; ``fold`` is a fold-of-cycles curve in
    the plane's (x, y) values to draw over it (core.fold_curve). ``title`` defaults to the sweep's id,
    name (escaped: it is stored text) and progress. ``cursor``, a value of the swept
    parameter, draws a bifurcation diagram's cursor line there (a phase diagram has
    none). Raises ValueError as the renderers do (e.g. a size too small)."""
    spec = diagram.spec
    if title is None:
        title = (f"sweep {diagram.id}: {terminal_safe(diagram.name)} "
                 f"({diagram.n_done}/{diagram.n_points} done)")
    # a phase diagram of several initial conditions draws their map (common regime,
    # "depends", failed...: Cell.drawn); a bifurcation diagram overlays each one's peaks
    runs = drawn(diagram).runs if spec.y is not None else diagram.runs
    xs = [r.x for r in runs]
    ys = [r.y for r in runs]
    peaks = [r.peaks for r in runs]
    # style keys, not bare regimes: a failed or cancelled run has none, and is no pending one
    regimes: list[str | None] = [run_key(r.regime, r.status) for r in runs]
    for _, _, px, py in diagram.unqueued():  # an adaptive sweep's levels still to come
        xs.append(px)
        ys.append(py)
        peaks.append([])
        regimes.append(None)
    x = spec.x
    if spec.y is None:
        return render_bifurcation(x.param, xs, peaks, regimes, log=x.spacing == "log",
                                  title=title, width=width, height=height, color=color,
                                  cursor=cursor)

    y = spec.y
    plane_ys = [math.nan if v is None else v for v in ys]  # every run of a 2-D sweep has y
    return render_phase_diagram(x.param, y.param, xs, plane_ys, regimes,
                                x_log=x.spacing == "log", y_log=y.spacing == "log",
                                hopf=plane_hopf(spec) if hopf else None, fold=fold, title=title,
                                width=width, height=height, color=color,
                                notes=adaptive_notes(diagram))


def adaptive_notes(diagram: SweepDiagram) -> list[str]:
    """The legend's line on an adaptive sweep: how much of it was computed (the terminal's
    and the figures' legends), e.g. "1,234 computed, 5,678 inferred (adaptive, 3 levels)"."""
    levels = diagram.spec.adaptive_levels
    if levels is None:
        return []
    counts = f"{diagram.n_computed:,} computed, {diagram.n_inferred:,} inferred"
    return [f"{counts} (adaptive, {levels} levels)"]
