"""The bifurcation diagram of a one-parameter sweep (the paper's Fig. 4A): the peak
clusters of m_y of each run against the swept parameter, marked by the run's regime.

A cursor (the run chosen in the application's bifurcation view) is a vertical line of
CURSOR_MARKER at its parameter value across the peaks' range: a character of its own
(no regime's ASCII marker, not the frame's │), so it shows with colour off. It is drawn
under the peaks, so the chosen run's own markers stay readable on it.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from slopetui.plots.canvas import (
    Series,
    axis_label,
    message_block,
    regime_legend,
    render,
    visible,
)
from slopetui.plots.regime_colors import REGIME_STYLES, regime_key

Y_LABEL = "m_y peaks"
#: The cursor's line: a dashed vertical, apart from the plot frame's solid one.
CURSOR_MARKER = "┆"
#: The terminal's own foreground, as the Hopf curve: legible on any background.
CURSOR_COLOR = "default"


def render_bifurcation(param: str, values: Sequence[float], peaks: Sequence[Sequence[float]],
                       regimes: Sequence[str | None], *, log: bool = False, title: str = "",
                       width: int = 80, height: int = 24, color: bool = True,
                       cursor: float | None = None) -> str:
    """Each run's peaks[i] (maxima of m_y in the analysis window, model units) plotted at
    its parameter value values[i], marked by regimes[i].

    Runs without peaks (sliding at rest, unstable, pending, and the style keys of runs
    without a result, regime_colors.run_key's "failed" and "cancelled") add no points but
    count in the legend, which gives runs per regime. Non-finite peaks, and with ``log`` a
    parameter value <= 0, are left out. ``cursor``, a parameter value, draws a vertical
    line there across the peaks' range (module docstring); none where the axis cannot
    show it. Returns exactly ``height`` lines of at most ``width`` columns; with ``color``
    False, no ANSI escapes. Raises ValueError for inputs of unequal length, an unknown
    regime, or a size too small.
    """
    keys = [regime_key(r) for r in regimes]
    if not len(values) == len(peaks) == len(keys):
        raise ValueError(f"values, peaks and regimes differ in length: "
                         f"{len(values)}, {len(peaks)}, {len(keys)}")
    series = _peak_series(np.asarray(values, dtype=float), peaks, keys, log)
    if not series:
        what = f"{len(keys)} runs, no peaks to plot" if keys else "no runs"
        prefix = f"{title}: " if title else ""
        return message_block(f"{prefix}{what} along {param}.", width, height)
    finite = np.asarray(values, dtype=float)[visible(np.asarray(values, dtype=float), log)]
    # plotext's xlim misplaces points on a log axis: pin the range on linear axes only
    x_range = (float(finite.min()), float(finite.max())) if finite.size and not log else None
    line = _cursor_line(cursor, series, log)
    return render(line + series, regime_legend(keys), x_label=axis_label(param), y_label=Y_LABEL,
                  x_log=log, y_log=False, title=title, width=width, height=height, color=color,
                  x_range=x_range)


def _cursor_line(cursor: float | None, series: list[Series], log: bool) -> list[Series]:
    """The cursor's vertical line from the lowest to the highest peak drawn (so the y
    range is the peaks' own), or nothing without a cursor the axis can show. Peaks all
    at one value (e.g. every run at rest) would make it one cell, under a marker: it
    then reaches 1 beyond them either way, as plotext's own range for one value does."""
    if cursor is None or not visible(np.array([cursor]), log)[0]:
        return []
    low = min(float(s.ys.min()) for s in series)
    high = max(float(s.ys.max()) for s in series)
    if low == high:
        low, high = low - 1.0, high + 1.0
    return [Series(np.array([cursor, cursor]), np.array([low, high]), CURSOR_MARKER,
                   CURSOR_COLOR, line=True)]


def _peak_series(values: np.ndarray, peaks: Sequence[Sequence[float]], keys: list[str],
                 log: bool) -> list[Series]:
    """One series per regime of (parameter value, peak) points, the most numerous first:
    where points share a terminal cell the later one wins, so rare regimes stay visible."""
    shown = visible(values, log)
    xs: dict[str, list[np.ndarray]] = {}
    ys: dict[str, list[np.ndarray]] = {}
    for value, run_peaks, key, ok in zip(values, peaks, keys, shown, strict=True):
        run = np.asarray(run_peaks, dtype=float).ravel()
        run = run[np.isfinite(run)]
        if ok and run.size:
            xs.setdefault(key, []).append(np.full(run.size, value))
            ys.setdefault(key, []).append(run)
    order = sorted(xs, key=lambda k: -sum(a.size for a in xs[k]))
    return [Series(np.concatenate(xs[k]), np.concatenate(ys[k]), REGIME_STYLES[k].marker,
                   REGIME_STYLES[k].color) for k in order]
