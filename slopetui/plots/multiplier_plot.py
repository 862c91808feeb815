"""An orbit's Floquet multipliers in the complex plane against the unit circle: the orbit
is stable when all of them but the flow's and the translation's (both 1) lie inside it.
The circle is a line in grey; a multiplier inside is 'o' in green, one on or outside '*'
in red, so that the verdict reads with colour off. The axes are square in model units
over at least [-1.2, 1.2], so the circle looks a circle as far as a terminal's cells
allow, and a multiplier far outside still shows."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from slopetui.plots.canvas import LegendEntry, Series, message_block, render

#: (marker, colour) of the circle, of a multiplier inside it, of one on or outside.
CIRCLE = ("·", "gray")
INSIDE = ("o", "green")
OUTSIDE = ("*", "red")

#: Points drawn along the circle: enough that it is a closed line at any terminal size.
CIRCLE_POINTS = 181

#: The half-width of the axes at least: the circle with a margin.
REACH = 1.2


def render_multipliers(pairs: Sequence[Sequence[float]], *, title: str = "", width: int = 80,
                       height: int = 24, color: bool = True) -> str:
    """The multipliers (``pairs``: [re, im] each) over the unit circle; exactly ``height``
    lines of at most ``width`` columns; a message block when there are none."""
    values = np.array([complex(re, im) for re, im in pairs], dtype=complex)
    if values.size == 0:
        return message_block(f"{title + ': ' if title else ''}no multipliers to draw.", width,
                             height)
    angle = np.linspace(0.0, 2 * np.pi, CIRCLE_POINTS)
    inside = np.abs(values) < 1.0
    series = [Series(np.cos(angle), np.sin(angle), *CIRCLE, line=True)]
    legend = [LegendEntry(*CIRCLE, "|μ| = 1")]
    for (marker, colour), chosen, words in ((INSIDE, inside, "inside"),
                                            (OUTSIDE, ~inside, "on or outside")):
        if chosen.any():
            series.append(Series(values[chosen].real, values[chosen].imag, marker, colour))
        legend.append(LegendEntry(marker, colour, f"{int(chosen.sum())} {words}"))
    finite = values[np.isfinite(values)]
    reach = max(REACH, float(np.max(np.abs(finite))) * 1.05 if finite.size else REACH)
    return render(series, legend, x_label="Re μ", y_label="Im μ", x_log=False, y_log=False,
                  title=title, width=width, height=height, color=color,
                  x_range=(-reach, reach), y_range=(-reach, reach))
