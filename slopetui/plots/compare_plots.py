"""Several runs overlaid in the terminal (the application's compare screen): m_y against
time over the last TIME_PERIODS periods of the slowest run (as the figure of a comparison:
a whole window of hundreds of periods is a solid band), and the phase portraits
(m_x − trend, m_y) over the whole window, one colour and one marker per run.

The single-run plots (slopetui.plots.run_plots) draw every trace in braille dots; here
the runs must stay apart with colour off too, so the first run keeps braille and the
others take ASCII markers, each in its own colour. m_x is detrended as in the run
detail (run_plots.detrend: on an orbit m_x is a ramp), each run by its own line. A run
at rest is the point it rests at, in a mark of its own named in the legend.
Time series keep the min/max envelope of run_plots (peaks at their true height).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from slopetui.plots.canvas import LegendEntry, Series, message_block, render
from slopetui.plots.run_plots import (
    FIXED_MARKER,
    MX_LABEL,
    MY_LABEL,
    TIME_PERIODS,
    TRACE_LEGEND_MARKER,
    TRACE_MARKER,
    detrend,
    envelope,
    envelope_points,
    finite,
    is_fixed_point,
    period_of,
    recent_start,
    stride,
)

#: (marker, colour) of the n-th run: braille first (the finest), then ASCII marks that
#: differ with colour off; colours from the regime palette's legible ones. A comparison
#: of more runs than this reuses the styles in order (the legend still names each run).
STYLES: tuple[tuple[str, str], ...] = (
    (TRACE_MARKER, "green"), ("•", "magenta"), ("+", "cyan"), ("x", "orange"), ("o", "red"),
    ("*", "blue+"),
)


@dataclass(frozen=True, slots=True)
class Overlay:
    """One run of a comparison: its label (e.g. "run 12: k 10") and its analysis-window
    trace in model units (t, m_x, m_y), with the dominant frequency of m_y
    (core.classify's Summary.frequency, 1/time; NaN: none)."""

    label: str
    t: np.ndarray
    m_x: np.ndarray
    m_y: np.ndarray
    frequency: float = float("nan")


def style(i: int) -> tuple[str, str]:
    """Marker and colour of the i-th run of a comparison."""
    return STYLES[i % len(STYLES)]


def _legend(runs: Sequence[Overlay], at_rest: Sequence[bool] = ()) -> list[LegendEntry]:
    """One entry per run; a run at rest (``at_rest``) by the mark its point is drawn in."""
    entries = []
    for i, run in enumerate(runs):
        marker, colour = style(i)
        if i < len(at_rest) and at_rest[i]:
            entries.append(LegendEntry(fixed_marker(i), colour, f"{run.label}: a fixed point"))
        else:
            entries.append(LegendEntry(TRACE_LEGEND_MARKER if marker == TRACE_MARKER else marker * 2,
                                       colour, run.label))
    return entries


def fixed_marker(i: int) -> str:
    """The mark of the i-th run when it rests: its own ASCII marker, or for the run drawn
    in braille (one dot, lost beside orbits) run_plots.FIXED_MARKER."""
    marker = style(i)[0]
    return FIXED_MARKER if marker == TRACE_MARKER else marker


def _finite(run: Overlay) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The run's (t, m_x, m_y) at the samples where all three are finite (run_plots.finite)."""
    t, m_x, m_y = finite(run.t, run.m_x, run.m_y)
    return t, m_x, m_y


def render_compare_time(runs: Sequence[Overlay], *, title: str = "", width: int = 80,
                        height: int = 24, color: bool = True) -> str:
    """m_y of every run against model time, overlaid, over the last TIME_PERIODS periods
    of the slowest run (the whole windows when no run has a period). Exactly ``height``
    lines of at most ``width`` columns; no ANSI escapes with ``color`` False."""
    traces = [_finite(run) for run in runs]
    start = recent_start([t for t, _, _ in traces],
                         [period_of(t, m_x, m_y, run.frequency)
                          for run, (t, m_x, m_y) in zip(runs, traces, strict=True)])
    series = []
    n = envelope_points(width)
    for i, (t, _, m_y) in enumerate(traces):
        shown = t >= start
        if shown.sum() >= 2:
            marker, colour = style(i)
            series.append(Series(*envelope(t[shown], m_y[shown], n), marker=marker, color=colour,
                                 line=True))
    if not series:
        return message_block("No samples in the analysis windows to plot.", width, height)
    whole = all(len(t) < 2 or start <= t[0] for t, _, _ in traces)
    x_label = "t" if whole else f"t (the last {TIME_PERIODS} periods)"
    return render(series, _legend(runs), x_label=x_label, y_label=MY_LABEL, x_log=False,
                  y_log=False, title=title, width=width, height=height, color=color)


def render_compare_phase(runs: Sequence[Overlay], *, title: str = "", width: int = 80,
                         height: int = 24, color: bool = True) -> str:
    """The phase portraits (m_x − trend, m_y) of every run, overlaid (each m_x detrended
    by its own least-squares line). Same size rules as render_compare_time."""
    series = []
    at_rest = []
    for i, run in enumerate(runs):
        t, m_x, m_y = _finite(run)
        rests = False
        if len(t) >= 2:
            x_rel, _ = detrend(t, m_x)
            marker, colour = style(i)
            rests = is_fixed_point(x_rel, m_y)
            if rests:  # its round-off as a line would be one dot: the point, marked
                series.append(Series(np.zeros(1), np.array([float(np.mean(m_y))]),
                                     marker=fixed_marker(i), color=colour))
            else:
                keep = stride(len(t))
                series.append(Series(x_rel[keep], m_y[keep], marker=marker, color=colour, line=True))
        at_rest.append(rests)
    if not series:
        return message_block("No samples in the analysis windows to plot.", width, height)
    return render(series, _legend(runs, at_rest), x_label=MX_LABEL, y_label=MY_LABEL, x_log=False,
                  y_log=False, title=title, width=width, height=height, color=color)
