"""Characteristic roots in the complex plane (Re against Im): the rest state's linear
stability at a glance. The delay factor's roots are 'o' (green where Re < 0, red where
Re > 0), the variance block's 'x'; a vertical line of '|' marks Re = 0, the stability
boundary."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from slopetui.plots.canvas import LegendEntry, Series, message_block, render

#: (marker, colour, legend words) of each kind of root.
STABLE = ("o", "green", "Re < 0")
UNSTABLE = ("o", "red", "Re > 0")
VARIANCE = ("x", "blue", "variance block")
AXIS = ("|", "gray", "Re = 0")


def render_roots(roots: Sequence[tuple[complex, str]], *, title: str = "", width: int = 80,
                 height: int = 24, color: bool = True) -> str:
    """``roots``: (value, factor) pairs, factor "delay" or "variance" (core.rest_stability
    .RestRoot). Exactly ``height`` lines of at most ``width`` columns."""
    if not roots:
        return message_block(f"{title + ': ' if title else ''}no roots to draw.", width, height)
    re = np.array([r.real for r, _ in roots])
    im = np.array([r.imag for r, _ in roots])
    delay = np.array([f == "delay" for _, f in roots])
    series: list[Series] = []
    legend: list[LegendEntry] = []
    for (marker, colour, words), mask in ((STABLE, delay & (re < 0)), (UNSTABLE, delay & (re > 0)),
                                          (VARIANCE, ~delay)):
        if mask.any():
            series.append(Series(re[mask], im[mask], marker, colour))
            legend.append(LegendEntry(marker, colour, f"{words} ({int(mask.sum())})"))
    low, high = float(min(im.min(), 0.0)), float(max(im.max(), 1e-9))
    series.insert(0, Series(np.zeros(2), np.array([low, high]), AXIS[0], AXIS[1], line=True))
    legend.append(LegendEntry(AXIS[0], AXIS[1], AXIS[2]))
    span = float(np.ptp(re)) or max(abs(float(re[0])), 1e-6)
    x_range = (min(float(re.min()), 0.0) - 0.05 * span, max(float(re.max()), 0.0) + 0.05 * span)
    return render(series, legend, x_label="Re λ", y_label="Im λ", x_log=False, y_log=False,
                  title=title, width=width, height=height, color=color, x_range=x_range)
