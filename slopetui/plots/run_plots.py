"""Plots of one run's traces (the run detail screen): m_x and m_y against time, the
phase portrait, the power spectrum of m_y and the running lambda_max estimate.

Decisions:

* **m_x is detrended.** dm_x/dt = m_y (eq. 6a), and on a limit cycle or a chaotic
  attractor m_y has a non-zero mean (the stored ``drift``), so over the analysis window
  m_x is a ramp with a small oscillation on it: at k = 12, tau = 2 it rises by 11 over
  100 time units while it oscillates by ~0.8. Plotted as is, the oscillation is a
  straight line and the (m_x, m_y) portrait an open spiral. Both plots therefore show
  m_x minus its least-squares line over the window, labelled "m_x − trend", and the
  legend gives the slope removed. The least-squares line, not the stored end-point
  drift, so that what is left has zero mean and no slope whatever the phase at the ends.
  A closed orbit of (m_x − trend, m_y) is a limit cycle of the model.
* **Sub-sampling.** A window of 1000 time units holds 1e5 samples; plotext's cost grows
  with the points it is given (~80 ms for 4000 joined points), and a terminal shows a
  few thousand at most. Each series keeps at most ``MAX_POINTS``. The time series and the
  spectrum keep the minimum and the maximum of y in each of one bucket per braille dot
  column (2 per terminal column), so peaks are drawn at their true height (a uniform
  stride would cut their tops and understate the amplitude) and nothing visible is lost;
  the spectrum's buckets are log-spaced to match its log frequency axis. The phase
  portrait and the lambda_max curve, which have no isolated extremes to lose, take a
  uniform stride.
* **The time series can show the last n periods** of the dominant frequency instead of
  the whole window (the run detail starts at TIME_PERIODS and zooms out with z): a
  1000-unit window holds ~400 periods at k = 12, τ = 2, a solid wall of braille at any
  terminal size. A fixed point has no period: it is shown whole.
* **A fixed point** (the sliding regime) has an orbit that round-off alone spreads over
  ~1e-16: the phase portrait marks the point (FIXED_MARKER, named in the legend) on a
  frame of the size of a cycle and says why, instead of magnifying the round-off to the
  whole canvas.
* **Markers.** Traces are drawn in braille dots (the finest plotext has); a second
  series in the same plot uses an ASCII marker, so the two stay apart with colour off.

All quantities are in model units: time in model time units, frequency in cycles per
time unit, lambda_max in 1 / time unit.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence

import numpy as np

from core.classify import AMPLITUDE_FLOOR
from slopetui.plots.canvas import LegendEntry, Series, message_block, note, render

#: At most this many points per plotted series (see the module docstring).
MAX_POINTS = 4000

#: Braille dots, and two braille cells that read as a short line in a legend.
TRACE_MARKER = "braille"
TRACE_LEGEND_MARKER = "⠤⠤"
#: m_x − trend in the time series, drawn under m_y: an ASCII dot, distinct from braille.
MX_MARKER = "."
MX_COLOR = "cyan"
MY_COLOR = "green"
#: The phase portrait, the spectrum and the lambda_max curve.
TRACE_COLOR = "green"
#: The zero line of the lambda_max plot: dashes in the terminal's own foreground, so a
#: curve converging onto zero (a limit cycle) stays visible on top of it.
ZERO_MARKER = "-"
ZERO_COLOR = "default"

#: A run at rest in a phase portrait: one full-cell mark (a braille dot would be lost),
#: on a frame of ±FIXED_FRAME model units around it, the scale of the paper's cycles
#: (k = 12, τ = 2: m_x − trend spans ~0.8, m_y ~2), so that the point reads as a point
#: and its round-off is not magnified.
FIXED_MARKER = "●"
FIXED_FRAME = 1.0

MX_LABEL = "m_x − trend"
MY_LABEL = "m_y"


def detrend(t: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, float]:
    """y minus its least-squares line in t, and the line's slope (units of y per time).

    Fewer than two points: y minus its mean and slope 0.
    """
    if len(y) < 2 or np.ptp(t) == 0.0:
        return y - (y.mean() if len(y) else 0.0), 0.0
    slope, intercept = np.polyfit(t, y, 1)
    return y - (slope * t + intercept), float(slope)


def stride(n: int, max_points: int = MAX_POINTS) -> slice:
    """A slice keeping every k-th of n points, k the smallest step leaving <= max_points."""
    return slice(None, None, max(1, math.ceil(n / max_points)))


def envelope_points(width: int) -> int:
    """Points an envelope of a plot ``width`` columns wide needs: a minimum and a
    maximum per braille dot column (two per terminal column), at most MAX_POINTS."""
    return min(MAX_POINTS, 4 * width)


def envelope(x: np.ndarray, y: np.ndarray, max_points: int = MAX_POINTS, *,
             log: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """(x, y) reduced to the minimum and the maximum of y in each of max_points / 2
    buckets of consecutive points, in their original order. Buckets are equal in count,
    or, with ``log``, grow geometrically (for a log x axis over a uniform x grid)."""
    n = len(y)
    if n <= max_points:
        return x, y
    buckets = max(1, max_points // 2)
    if log:
        edges = np.unique(np.geomspace(1, n + 1, buckets + 1).astype(int) - 1)
    else:
        edges = np.linspace(0, n, buckets + 1).astype(int)
    keep: list[int] = []
    for lo, hi in itertools.pairwise(edges):
        if hi > lo:
            segment = y[lo:hi]
            keep.extend(sorted({lo + int(np.argmin(segment)), lo + int(np.argmax(segment))}))
    idx = np.asarray(keep, dtype=int)
    return x[idx], y[idx]


def finite(*arrays: np.ndarray) -> tuple[np.ndarray, ...]:
    """The arrays as flat float arrays, keeping the positions where all of them are finite.

    Raises ValueError for arrays of unequal length.
    """
    arrs = [np.asarray(a, dtype=float).ravel() for a in arrays]
    if len({len(a) for a in arrs}) > 1:
        raise ValueError(f"arrays differ in length: {', '.join(str(len(a)) for a in arrs)}")
    ok = np.logical_and.reduce([np.isfinite(a) for a in arrs])
    return tuple(a[ok] for a in arrs)


def is_fixed_point(x_rel: np.ndarray, m_y: np.ndarray) -> bool:
    """The orbit rests: m_x − trend and m_y both vary by less than AMPLITUDE_FLOOR
    (core.classify), so what is left of them is round-off (module docstring)."""
    return bool(np.ptp(x_rel) < AMPLITUDE_FLOOR and np.ptp(m_y) < AMPLITUDE_FLOOR)


def log_spectrum(freq: np.ndarray, power: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The bins of a power spectrum that have a logarithm: finite, frequency > 0 (not the
    zero bin) and power > 0. Raises ValueError for arrays of unequal length."""
    freq, power = finite(freq, power)
    shown = (freq > 0.0) & (power > 0.0)
    return freq[shown], power[shown]


#: A time series of many runs, or on paper, shows this many periods of the dominant
#: frequency: the paper's window of 1000 time units holds ~400 periods at k = 12, τ = 2,
#: a solid band however it is drawn (the figures, the compare screen).
TIME_PERIODS = 10


def period_of(t: np.ndarray, m_x: np.ndarray, m_y: np.ndarray, frequency: float) -> float | None:
    """1 / ``frequency`` (the classifier's dominant frequency of m_y, Summary.frequency)
    for a finite trace that moves; None at a fixed point (its spectrum is round-off),
    without samples or without a frequency."""
    if len(t) < 2 or is_fixed_point(detrend(t, m_x)[0], m_y):
        return None
    return 1.0 / frequency if math.isfinite(frequency) and frequency > 0.0 else None


def recent_start(ts: Sequence[np.ndarray], periods: Sequence[float | None],
                 n: int = TIME_PERIODS) -> float:
    """Where a shared time axis starts: n periods of the longest of ``periods`` before
    the latest end of the traces ``ts``, not before their earliest start; the earliest
    start when no trace has a period (0.0 with no samples at all)."""
    sampled = [t for t in ts if len(t) >= 2]
    first = min((float(t[0]) for t in sampled), default=0.0)
    last = max((float(t[-1]) for t in sampled), default=0.0)
    known = [p for p in periods if p is not None and math.isfinite(p)]
    return max(first, last - n * max(known)) if known else first


def _trace_legend(text: str, color_name: str = TRACE_COLOR) -> LegendEntry:
    return LegendEntry(TRACE_LEGEND_MARKER, color_name, text)


def render_time_series(t: np.ndarray, m_x: np.ndarray, m_y: np.ndarray, *,
                       frequency: float = math.nan, periods: int | None = None,
                       title: str = "", width: int = 80, height: int = 24,
                       color: bool = True) -> str:
    """m_x − trend and m_y against time t (model units): the last ``periods`` periods of
    ``frequency`` (the classifier's dominant frequency of m_y, Summary.frequency) before
    the window's end, or the whole analysis window with ``periods`` None, at a fixed
    point, or without a frequency. The x label says which ("t (the last 10 periods)",
    "t (the whole window)").

    A window holds hundreds of periods: drawn whole, they fill the canvas with braille
    and no cycle can be read. m_x is detrended over the whole window before it is cut
    (module docstring), so a shorter span is a true zoom of the whole plot; the legend
    gives the slope removed. Non-finite samples are left out. Returns exactly ``height``
    lines of at most ``width`` columns; with ``color`` False, no ANSI escapes. Raises
    ValueError for arrays of unequal length or a size too small.
    """
    t, m_x, m_y = finite(t, m_x, m_y)
    if len(t) < 2:
        return message_block("No samples in the analysis window to plot.", width, height)
    x_rel, slope = detrend(t, m_x)
    start = float(t[0])
    if periods is not None:  # without a period (a fixed point), recent_start gives t[0]
        start = recent_start([t], [period_of(t, m_x, m_y, frequency)], periods)
    shown = t >= start
    if start <= float(t[0]) or shown.sum() < 2:  # n periods are the window, or more
        shown = np.ones(len(t), dtype=bool)
        x_label = "t (the whole window)"
    else:
        x_label = f"t (the last {periods} periods)"
    t, x_rel, m_y = t[shown], x_rel[shown], m_y[shown]
    n = envelope_points(width)
    series = [Series(*envelope(t, x_rel, n), marker=MX_MARKER, color=MX_COLOR, line=True),
              Series(*envelope(t, m_y, n), marker=TRACE_MARKER, color=MY_COLOR, line=True)]
    legend = [LegendEntry(MX_MARKER, MX_COLOR, f"{MX_LABEL} (slope {slope:.4g} removed)"),
              _trace_legend(MY_LABEL, MY_COLOR)]
    return render(series, legend, x_label=x_label, y_label="", x_log=False, y_log=False,
                  title=title, width=width, height=height, color=color)


def render_phase_portrait(t: np.ndarray, m_x: np.ndarray, m_y: np.ndarray, *,
                          title: str = "", width: int = 80, height: int = 24,
                          color: bool = True) -> str:
    """The orbit (m_x − trend, m_y) over the analysis window, points joined in time order.

    ``t`` (model time) is needed only to detrend m_x (module docstring): a limit cycle is
    a closed curve, a period-n orbit n loops, a chaotic one a filled band. Returns exactly
    ``height`` lines of at most ``width`` columns; with ``color`` False, no ANSI escapes.
    Raises ValueError for arrays of unequal length or a size too small.
    """
    t, m_x, m_y = finite(t, m_x, m_y)
    if len(t) < 2:
        return message_block("No samples in the analysis window to plot.", width, height)
    x_rel, slope = detrend(t, m_x)
    if is_fixed_point(x_rel, m_y):
        rest = float(np.mean(m_y))
        point = Series(np.zeros(1), np.array([rest]), marker=FIXED_MARKER, color=TRACE_COLOR)
        legend = [LegendEntry(FIXED_MARKER, TRACE_COLOR, f"a fixed point: m_y = {rest:.6g}"),
                  note(f"m_x − trend and m_y vary by less than {AMPLITUDE_FLOOR:g} over the "
                       f"window (m_x slope {slope:.4g})")]
        return render([point], legend, x_label=MX_LABEL, y_label=MY_LABEL, x_log=False,
                      y_log=False, title=title, width=width, height=height, color=color,
                      x_range=(-FIXED_FRAME, FIXED_FRAME),
                      y_range=(rest - FIXED_FRAME, rest + FIXED_FRAME))
    keep = stride(len(t))
    series = [Series(x_rel[keep], m_y[keep], marker=TRACE_MARKER, color=TRACE_COLOR, line=True)]
    legend = [note(f"m_x detrended: slope {slope:.4g} removed")]
    return render(series, legend, x_label=MX_LABEL, y_label=MY_LABEL, x_log=False, y_log=False,
                  title=title, width=width, height=height, color=color)


def render_spectrum(freq: np.ndarray, power: np.ndarray, *, title: str = "", width: int = 80,
                    height: int = 24, color: bool = True) -> str:
    """log10 of the power spectrum of m_y (core.classify.power_spectrum) against frequency
    on a log axis.

    freq in cycles per time unit; power in arbitrary units (Hann-windowed periodogram).
    log10 is taken here, on a linear axis, because plotext's log axis labels its ticks
    with 20 digits. The zero-frequency bin and bins with power <= 0 have no logarithm and
    are left out; the legend gives the frequency of the largest peak. Returns exactly
    ``height`` lines of at most ``width`` columns; with ``color`` False, no ANSI escapes.
    Raises ValueError for arrays of unequal length or a size too small.
    """
    freq, power = log_spectrum(freq, power)
    if len(freq) < 2:
        return message_block("m_y is constant over the window: no spectrum to plot.",
                             width, height)
    peak = float(freq[int(np.argmax(power))])
    series = [Series(*envelope(freq, np.log10(power), envelope_points(width), log=True), marker=TRACE_MARKER,
                     color=TRACE_COLOR, line=True)]
    legend = [_trace_legend("log10 power of m_y"), note(f"largest peak at f = {peak:.4g}")]
    return render(series, legend, x_label="frequency (1/t)", y_label="", x_log=True,
                  y_log=False, title=title, width=width, height=height, color=color)


def render_lyapunov(t: np.ndarray, lam: np.ndarray, *, estimate: str = "", note_text: str = "",
                    title: str = "", width: int = 80, height: int = 24, color: bool = True) -> str:
    """The running estimate lambda(t) (core.lyapunov.running; 1 / time unit) against
    model time t on a log axis, over a dashed zero line.

    The log time axis gives the early transient and the late convergence comparable
    room. ``estimate`` (e.g. "0.0008(9)"), when given, is the block-averaged value
    shown in the legend; ``note_text`` a further legend line (which map the estimate
    belongs to and its bias: core.lyapunov_bias.bias_note). Returns exactly ``height``
    lines of at most ``width`` columns; with ``color`` False, no ANSI escapes. Raises
    ValueError for arrays of unequal length or a size too small.
    """
    t, lam = finite(t, lam)
    shown = t > 0.0
    t, lam = t[shown], lam[shown]
    if len(t) < 2:
        return message_block("No lambda_max estimate: the run kept no log-growths.",
                             width, height)
    keep = stride(len(t))
    zero = Series(np.array([t[0], t[-1]]), np.zeros(2), marker=ZERO_MARKER, color=ZERO_COLOR,
                  line=True)
    curve = Series(t[keep], lam[keep], marker=TRACE_MARKER, color=TRACE_COLOR, line=True)
    legend = [_trace_legend("running λ(t)"), LegendEntry(ZERO_MARKER, ZERO_COLOR, "0")]
    if estimate:
        legend.append(note(f"λmax = {estimate}"))
    if note_text:
        legend.append(note(note_text))
    return render([zero, curve], legend, x_label="t", y_label="", x_log=True, y_log=False,
                  title=title, width=width, height=height, color=color)
