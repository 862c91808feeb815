"""A hysteresis sweep drawn as one bifurcation diagram: the amplitude (peak to peak of m_y)
each point of the up branch and of the down branch ends with, against the parameter.
Where the two branches differ the outcome depends on the path taken: the bistable band.
Up is '^' in blue, down 'v' in magenta, so the branches read with colour off; where both
fall on one cell the down branch, drawn last, shows."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from slopetui.plots.branch_plot import Y_LABEL
from slopetui.plots.canvas import LegendEntry, Series, axis_label, message_block, render

#: (marker, colour, legend name) of each branch.
UP = ("^", "blue", "up")
DOWN = ("v", "magenta", "down")


def render_hysteresis(param: str, up: Sequence[Mapping[str, Any]],
                      down: Sequence[Mapping[str, Any]], *, title: str = "",
                      width: int = 80, height: int = 24, color: bool = True) -> str:
    """The points of both branches (records with ``value`` and ``amplitude``, model
    units); non-finite ones (a run that left the finite range) are left out. Exactly
    ``height`` lines of at most ``width`` columns; a message block when nothing is
    plottable; no ANSI escapes with ``color`` False."""
    series: list[Series] = []
    legend: list[LegendEntry] = []
    for (marker, colour, name), points in ((UP, up), (DOWN, down)):
        xs = np.array([p["value"] for p in points], dtype=float)
        ys = np.array([p["amplitude"] for p in points], dtype=float)
        ok = np.isfinite(xs) & np.isfinite(ys)
        if ok.any():
            series.append(Series(xs[ok], ys[ok], marker, colour))
        legend.append(LegendEntry(marker, colour, f"{name} {int(ok.sum())}"))
    if not series:
        return message_block(f"{title + ': ' if title else ''}no points to draw along {param}.",
                             width, height)
    return render(series, legend, x_label=axis_label(param), y_label=Y_LABEL, x_log=False,
                  y_log=False, title=title, width=width, height=height, color=color)
