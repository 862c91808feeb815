"""A curve in two parameters (core.curve_start) in its plane: the fold of cycles, period
doubling, torus bifurcation or Hopf curve as points, the first parameter across and the
second up (the phase diagrams' orientation: k across, tau up), and its codimension-two
points marked by a capital letter of their own, so that the plane reads with colour off.
A Hopf curve's points are drawn by the sign of l1: '+' subcritical, '-' supercritical.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Mapping, Sequence
from types import MappingProxyType
from typing import Any

import numpy as np

from slopetui.plots.branch_plot import BranchStyle
from slopetui.plots.canvas import LegendEntry, Series, axis_label, message_block, render

FOLD = BranchStyle("orange", "o", "fold of cycles")
FLIP = BranchStyle("magenta", "o", "period doubling")
TORUS = BranchStyle("blue", "o", "torus")
#: How each kind of curve from a bifurcation of cycles draws its points.
KIND_STYLES: Mapping[str, BranchStyle] = MappingProxyType({"fold": FOLD, "pd": FLIP,
                                                           "ns": TORUS})
SUBCRITICAL = BranchStyle("red", "+", "Hopf, l1 > 0")
SUPERCRITICAL = BranchStyle("green", "-", "Hopf, l1 < 0")
#: By codimension-two type (core.codim2, core.curve_start), in legend order.
CODIM2_STYLES: Mapping[str, BranchStyle] = MappingProxyType({
    "bautin": BranchStyle("magenta", "B", "bautin"),
    "cusp": BranchStyle("cyan", "C", "cusp"),
    "fold-flip": BranchStyle("blue", "D", "fold-flip"),
    "fold-ns": BranchStyle("blue", "T", "fold-ns"),
    "resonance-1:2": BranchStyle("default", "R", "resonance-1:2"),
    "flip-ns": BranchStyle("blue", "T", "flip-ns"),
    "undetermined": BranchStyle("default", "?", "undetermined"),
    "resonance-1:1": BranchStyle("default", "R", "resonance-1:1"),
    "resonance-1:3": BranchStyle("default", "R", "resonance-1:3"),
    "resonance-1:4": BranchStyle("default", "R", "resonance-1:4"),
    "double-ns": BranchStyle("blue", "T", "double-ns"),
})
OTHER = BranchStyle("default", "?", "other")


def render_curve(name: str, second: str, points: Sequence[Mapping[str, Any]],
                 found: Sequence[Mapping[str, Any]], *, title: str = "", width: int = 80,
                 height: int = 24, color: bool = True, kind: str = "fold") -> str:
    """The curve's ``points`` (records keyed by ``name`` and ``second``, a Hopf point's
    with ``l1``) and its codimension-two points ``found`` (records with ``type`` and both
    parameters). Returns exactly ``height`` lines of at most ``width`` columns (a message
    block with no point to draw); with ``color`` False, no ANSI escapes. ``kind``: the
    curve's (fold, hopf, pd, ns), which names its points."""
    xs = np.array([_number(p.get(name)) for p in points], dtype=float)
    ys = np.array([_number(p.get(second)) for p in points], dtype=float)
    shown = np.isfinite(xs) & np.isfinite(ys)
    if not shown.any():
        prefix = f"{title}: " if title else ""
        return message_block(f"{prefix}no points yet on this curve in ({name}, {second}).",
                             width, height)
    l1 = np.array([_number(p.get("l1")) for p in points], dtype=float)
    series: list[Series] = []
    legend: list[LegendEntry] = []
    groups = ((KIND_STYLES.get(kind, FOLD), shown & np.isnan(l1)),
              (SUBCRITICAL, shown & (l1 > 0)), (SUPERCRITICAL, shown & (l1 < 0)))
    for style, mask in groups:
        if mask.any():
            series.append(Series(xs[mask], ys[mask], style.marker, style.color))
            legend.append(LegendEntry(style.marker, style.color,
                                      f"{style.label} {int(mask.sum())}"))
    for kind, n in Counter(str(c["type"]) for c in found).items():
        style = CODIM2_STYLES.get(kind, OTHER)
        at = [(float(c[name]), float(c[second])) for c in found if str(c["type"]) == kind
              and math.isfinite(_number(c.get(name))) and math.isfinite(_number(c.get(second)))]
        if at:
            series.append(Series(np.array([a for a, _ in at]), np.array([b for _, b in at]),
                                 style.marker, style.color))
        legend.append(LegendEntry(style.marker, style.color, f"{kind} {n}"))
    all_x = np.concatenate([s.xs for s in series])
    return render(series, legend, x_label=axis_label(name), y_label=axis_label(second),
                  x_log=False, y_log=False, title=title, width=width, height=height,
                  color=color, x_range=(float(all_x.min()), float(all_x.max())))


def _number(x: Any) -> float:
    return math.nan if x is None else float(x)
