"""Recomputed runs as a publication figure: the file counterpart of
slopetui.plots.run_plots (the run detail screen), drawing the same four things.

One run gives four panels: the time series (m_x − trend and m_y against t), the phase
portrait (m_x − trend, m_y) over the analysis window, the spectrum (log10 power of m_y
against frequency, log axis, the largest peak marked) and the running λ(t) on a log time
axis over a zero line, with the block-averaged estimate and which map it belongs to
(Traces.lambda_note). Two or more runs give a **comparison**: m_y against t and the phase
portraits, overlaid, one colour per run, each named in the legend as the compare screen
names it (slopetui.sweeps.run_labels: the inputs that differ between the runs, and the
run's regime).

Decisions (as on the screen, slopetui.plots.run_plots, whose reasons hold here too):

* **m_x is detrended**: dm_x/dt = m_y has a non-zero mean on a cycle, so m_x is a ramp
  with the oscillation on it; the figures show m_x minus its least-squares line over the
  window and give the slope removed. ``detrend``, the fixed-point test and which samples
  and spectrum bins are drawn are the terminal's (slopetui.plots.run_plots), imported.
* **A fixed point** (sliding) has an orbit that round-off spreads over ~1e-16; its phase
  portrait marks the point with a marker named in the legend, and says why
  (core.classify.AMPLITUDE_FLOOR), rather than magnifying the noise to the whole panel
  or drawing a line no wider than a pixel (in a comparison, beside orbits); its
  spectrum, of round-off too, is not drawn (the terminal draws it).
* **The time series shows the last TIME_PERIODS periods** of the dominant frequency (the
  spectrum's largest peak), not the whole window as the terminal does: the paper's window
  of 1000 time units holds ~400 periods at k = 12, τ = 2, which on paper is a solid band
  (the terminal's envelope is the same band). The x label says what is shown; a window
  shorter than that, or a run without a period, is shown whole. The phase portrait and
  the data table keep the whole window. A comparison shows one span for all its runs:
  TIME_PERIODS of the slowest one's period, before the latest window's end.
* **Dense lines are rasterised** above RASTER_LINE_POINTS points (at RASTER_DPI in a PDF
  or SVG; axes and text stay vector). Measured on one run figure of a noisy cycle (a sine
  with 5 % noise, all four panels): 1e5 samples make a 1.14 MB PDF with vector traces
  against 0.25 MB rasterised; at 5,000 samples it is 126 kB against 145 kB, about where
  they cross. All samples are drawn: no sub-sampling, so no peak is cut.
* **The data table** ("traces", long format: run_id, panel, x, y) holds what each panel
  draws over the whole window (the spectrum's y is log10 power), at most MAX_TABLE_ROWS
  rows per run and panel: a longer series is strided evenly. The paper's window (1000
  time units sampled every 0.01, core.solve.WINDOW_SAMPLE_DT: 1e5 samples) keeps every
  5th sample, a step of 0.05, still 50 samples a period at k = 12, τ = 2 (period 2.5);
  one run's CSV is then ~4 MB rather than ~20 MB.
"""

from __future__ import annotations

import math
import textwrap
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from core.classify import AMPLITUDE_FLOOR
from slopetui.figures.canvas import empty_panel, new_figure, no_offset, set_title, time_origin
from slopetui.figures.labels import (
    FREQUENCY_LABEL,
    LAMBDA_LABEL,
    MX_LABEL,
    MY_LABEL,
    POWER_LABEL,
    TIME_LABEL,
    plain,
    symbol,
    time_label,
)
from slopetui.figures.output import Drawing, Table
from slopetui.figures.style import GUIDE_COLOR, MX_COLOR, MY_COLOR, PEAK_COLOR, TRACE_COLOR, run_style
from slopetui.plots.run_plots import (
    TIME_PERIODS,
    detrend,
    finite,
    is_fixed_point,
    log_spectrum,
    period_of,
    recent_start,
)
from slopetui.sweeps.recompute import lambda_text
from slopetui.sweeps.run_labels import INPUTS, differing, run_labels, value_text

if TYPE_CHECKING:
    from matplotlib.artist import Artist
    from matplotlib.axes import Axes

    from slopetui.sweeps.recompute import StoredRun, Traces

__all__ = ["COMPARE_SIZE", "MAX_TABLE_ROWS", "RASTER_LINE_POINTS", "RUN_SIZE", "run_drawing"]

#: One run's four panels (inches).
RUN_SIZE: tuple[float, float] = (10.0, 7.5)
#: A comparison's two panels side by side, the legend under them (inches).
COMPARE_SIZE: tuple[float, float] = (10.0, 4.5)
#: Lines with more points than this are rasterised (module docstring).
RASTER_LINE_POINTS = 5000
#: Rows per run and panel in the data table at most (module docstring).
MAX_TABLE_ROWS = 20_000
#: The parameters in a run's title, in the order the paper discusses them.
TITLE_PARAMS: tuple[str, ...] = ("k", "tau", "a", "b", "c", "d", "v", "delta")
#: "k = 12" stays on one line when a title wraps (textwrap breaks at spaces, not these).
EQUALS = "\u00a0=\u00a0"
#: A legend line of a quarter panel wraps at about this many characters.
LEGEND_WRAP = 48
TRACE_WIDTH = 0.8
#: A run at rest in a phase portrait: a filled circle of this size (points), about
#: three times a trace's width, so that it reads as a point on an orbit's scale.
FIXED_MARKER, FIXED_SIZE = "o", 7.0

#: The panels of the data table.
PANEL_MX, PANEL_MY, PANEL_PHASE = "time_m_x_detrended", "time_m_y", "phase"
PANEL_SPECTRUM, PANEL_LAMBDA = "spectrum", "lambda"


def run_drawing(runs: Sequence[tuple[StoredRun, Traces]], *, title: str | None = None) -> Drawing:
    """One run's four panels, or for two or more runs their comparison, with the data
    table "traces". ``title`` (plain text) defaults to the run, its parameters, solver
    and stored result; for a comparison, the runs and the parameters they share. Raises
    ValueError for no runs."""
    if not runs:
        raise ValueError("no runs to draw: give one or more (run, traces) pairs")
    if len(runs) == 1:
        run, traces = runs[0]
        return _single(run, traces, title)
    return _comparison(runs, title)


def _time_axis(ax: Axes, t: np.ndarray, start: float) -> float:
    """Label the time axis of a window ``t`` (its first and last time) shown from
    ``start``, and return the origin its samples are drawn from (canvas.time_origin:
    0, or a round time named in the label, so that no offset text overprints it)."""
    origin = time_origin(max(start, float(t[0])), float(t[-1]))
    no_offset(ax)
    label = time_label(origin)
    if start > float(t[0]):
        label += (f": the last {TIME_PERIODS} periods, {float(t[-1]) - start:.4g} "
                  f"of {float(t[-1] - t[0]):.4g}")
    ax.set_xlabel(label)
    return origin


def _rows(run_id: int, panel: str, x: np.ndarray, y: np.ndarray) -> list[tuple[Any, ...]]:
    keep = slice(None, None, max(1, math.ceil(len(x) / MAX_TABLE_ROWS)))
    return [(run_id, panel, a, b) for a, b in zip(x[keep].tolist(), y[keep].tolist(), strict=True)]


def _line(ax: Axes, x: np.ndarray, y: np.ndarray, **style: Any) -> None:
    style.setdefault("linewidth", TRACE_WIDTH)
    ax.plot(x, y, rasterized=len(x) > RASTER_LINE_POINTS, **style)


def _note(text: str, *, safe: bool = False) -> Artist:
    """A legend line without a handle, wrapped; plain text (labels.plain) unless ``safe``
    (written here, with mathtext meant)."""
    from matplotlib.patches import Rectangle

    shown = text if safe else plain(text)
    return Rectangle((0, 0), 0, 0, fill=False, edgecolor="none",
                     label=textwrap.fill(shown, LEGEND_WRAP, break_long_words=False))


# -- one run --------------------------------------------------------------------------------

def _single(run: StoredRun, traces: Traces, title: str | None) -> Drawing:
    fig = new_figure(RUN_SIZE)
    (ax_time, ax_phase), (ax_spec, ax_lam) = fig.subplots(2, 2)
    rows: list[tuple[Any, ...]] = []
    rows += _time_and_phase(ax_time, ax_phase, run.id, traces)
    rows += _spectrum(ax_spec, run.id, traces)
    rows += _lyapunov(ax_lam, run.id, traces)
    set_title(fig, _run_title(run) if title is None else title)
    return Drawing(fig, (Table("traces", ("run_id", "panel", "x", "y"), rows),))


def _time_and_phase(ax_time: Axes, ax_phase: Axes, run_id: int,
                    traces: Traces) -> list[tuple[Any, ...]]:
    ax_phase.set_title("phase portrait", fontsize=10)
    t, m_x, m_y = finite(traces.t, traces.m_x, traces.m_y)
    if len(t) < 2:
        ax_time.set_title("time series", fontsize=10)
        empty_panel(ax_time, "No samples in the analysis window.")
        empty_panel(ax_phase, "No samples in the analysis window.")
        return []
    x_rel, slope = detrend(t, m_x)
    fixed = is_fixed_point(x_rel, m_y)
    start = recent_start([t], [None if fixed else period_of(t, m_x, m_y, traces.summary.frequency)])
    shown = t >= start
    origin = _time_axis(ax_time, t, start)
    _line(ax_time, t[shown] - origin, x_rel[shown], color=MX_COLOR,
          label=f"{MX_LABEL} (slope {slope:.4g} removed)")
    _line(ax_time, t[shown] - origin, m_y[shown], color=MY_COLOR, label=MY_LABEL)
    # the legend names the panel, above it: inside it would hide the oscillation
    ax_time.legend(loc="lower center", bbox_to_anchor=(0.5, 1.0), ncols=2, frameon=False,
                   fontsize=9)
    ax_phase.set_xlabel(MX_LABEL)
    ax_phase.set_ylabel(MY_LABEL)
    if fixed:
        # the orbit is round-off: mark the point, do not magnify the noise
        point = _fixed_point(ax_phase, m_y, TRACE_COLOR,
                             f"a fixed point: $m_y$ = {float(np.mean(m_y)):.6g}")
        ax_phase.legend(handles=[point, _note(
            f"m_x − trend and m_y vary by less than {AMPLITUDE_FLOOR:g} over the window "
            f"(m_x slope {slope:.4g})", safe=True)], loc="upper left", fontsize=8)
    else:
        _line(ax_phase, x_rel, m_y, color=TRACE_COLOR)
        ax_phase.legend(handles=[_note(f"$m_x$ detrended: slope {slope:.4g} removed", safe=True)],
                        loc="upper right", fontsize=8, handlelength=0, handletextpad=0)
    return (_rows(run_id, PANEL_MX, t, x_rel) + _rows(run_id, PANEL_MY, t, m_y)
            + _rows(run_id, PANEL_PHASE, x_rel, m_y))


def _fixed_point(ax: Axes, m_y: np.ndarray, color: str, label: str | None = None) -> Artist:
    """A run at rest drawn as the point it rests at, (0, mean m_y), in a marker large
    enough to see beside orbits: as a line its round-off samples span ~1e-16, less than a
    pixel, and nothing at all would show. Returns the marker, for a legend."""
    (point,) = ax.plot([0.0], [float(np.mean(m_y))], linestyle="none", marker=FIXED_MARKER,
                       markersize=FIXED_SIZE, color=color, label=label, zorder=4)
    return point


def _spectrum(ax: Axes, run_id: int, traces: Traces) -> list[tuple[Any, ...]]:
    ax.set_title("spectrum of $m_y$", fontsize=10)
    _, m_y = finite(traces.t, traces.m_y)
    if len(m_y) >= 2 and np.ptp(m_y) < AMPLITUDE_FLOOR:
        # a fixed point: what the spectrum would show is round-off (~1e-30)
        empty_panel(ax, f"m_y varies by less than {AMPLITUDE_FLOOR:g} over the window: "
                        "a fixed point, no spectrum to plot.")
        return []
    freq, power = log_spectrum(traces.freq, traces.power)  # the bins that have a log
    if len(freq) < 2:
        empty_panel(ax, "m_y is constant over the window: no spectrum to plot.")
        return []
    log_power = np.log10(power)
    _line(ax, freq, log_power, color=TRACE_COLOR)
    i = int(np.argmax(power))
    ax.plot([freq[i]], [log_power[i]], "o", color=PEAK_COLOR, markersize=5,
            label=f"largest peak at f = {freq[i]:.4g}")
    ax.set_xscale("log")
    ax.set_xlabel(FREQUENCY_LABEL)
    ax.set_ylabel(POWER_LABEL)
    # the power falls with frequency: the lower left is where the curve rarely goes
    ax.legend(loc="lower left", fontsize=8)
    return _rows(run_id, PANEL_SPECTRUM, freq, log_power)


def _lyapunov(ax: Axes, run_id: int, traces: Traces) -> list[tuple[Any, ...]]:
    lam_t, lam = finite(traces.lam_t, traces.lam)
    shown = lam_t > 0.0  # a log time axis
    lam_t, lam = lam_t[shown], lam[shown]
    if len(lam_t) < 2:
        ax.set_title("largest Lyapunov exponent", fontsize=10)
        empty_panel(ax, "No λmax estimate: the run kept no log-growths.")
        return []
    _line(ax, lam_t, lam, color=TRACE_COLOR, label="running λ(t)", zorder=3)
    ax.axhline(0.0, color=GUIDE_COLOR, linestyle="--", linewidth=0.8, label="0", zorder=2)
    ax.set_xscale("log")
    ax.set_xlabel(TIME_LABEL)
    ax.set_ylabel(LAMBDA_LABEL)
    handles, _ = ax.get_legend_handles_labels()  # the curve, then the zero line
    if traces.lyap is not None:
        handles.append(_note(f"λmax = {traces.lyap.format()}"))
    if traces.lambda_note:
        handles.append(_note(traces.lambda_note))
    # above the panel, as the time series' legend: the notes are long, and inside they
    # would hide the early transient or the convergence
    ax.legend(handles=handles, loc="lower center", bbox_to_anchor=(0.5, 1.0), ncols=2,
              frameon=False, fontsize=8)
    return _rows(run_id, PANEL_LAMBDA, lam_t, lam)


def _run_title(run: StoredRun) -> str:
    params = ", ".join(f"{symbol(n)}{EQUALS}{getattr(run, n):g}" for n in TITLE_PARAMS)
    return (f"run {run.id} (sweep {run.sweep_id})\n{params}\n"
            f"{run.method}, dt {run.dt:g}, t_end {run.t_end:g}, window {run.window:g} · "
            f"stored: {_stored_result(run)}")


def _stored_result(run: StoredRun) -> str:
    if run.inferred:
        return f"inferred {run.regime}" if run.done else f"inferred, {run.status}"
    if not run.done:
        return f"no result ({run.status})"
    return f"{run.regime}, λmax {lambda_text(run.lambda_max, run.lambda_err)}"


# -- a comparison ---------------------------------------------------------------------------

def _comparison(runs: Sequence[tuple[StoredRun, Traces]], title: str | None) -> Drawing:
    from matplotlib.lines import Line2D

    fig = new_figure(COMPARE_SIZE)
    ax_time, ax_phase = fig.subplots(1, 2)
    ax_time.set_title("$m_y$ against time", fontsize=10)
    ax_phase.set_title("phase portraits", fontsize=10)
    stored = [run for run, _ in runs]
    differ = differing(stored)
    # the compare screen's labels, as plain text ("$" is no mathtext)
    labels = [plain(label) for label in run_labels(stored)]
    rows: list[tuple[Any, ...]] = []
    handles: list[Artist] = []
    series = [finite(traces.t, traces.m_x, traces.m_y) for _, traces in runs]
    # one time span for all: TIME_PERIODS of the slowest run's period, before the last end
    start = recent_start([t for t, _, _ in series],
                         [period_of(t, m_x, m_y, traces.summary.frequency)
                          for (_, traces), (t, m_x, m_y) in zip(runs, series, strict=True)])
    ends = [float(t[i]) for t, _, _ in series if len(t) >= 2 for i in (0, -1)]
    origin = _time_axis(ax_time, np.array([min(ends, default=0.0), max(ends, default=0.0)]), start)
    for i, (run, _) in enumerate(runs):
        color, dash = run_style(i)
        t, m_x, m_y = series[i]
        label = labels[i]
        marker = "none"
        if len(t) >= 2:
            x_rel, _ = detrend(t, m_x)
            shown = t >= start
            _line(ax_time, t[shown] - origin, m_y[shown], color=color, linestyle=dash)
            if is_fixed_point(x_rel, m_y):
                _fixed_point(ax_phase, m_y, color)
                marker, label = FIXED_MARKER, f"{label}: a fixed point, marked"
            else:
                _line(ax_phase, x_rel, m_y, color=color, linestyle=dash)
            rows += _rows(run.id, PANEL_MY, t, m_y) + _rows(run.id, PANEL_PHASE, x_rel, m_y)
        else:
            label += " (no samples)"
        handles.append(Line2D([], [], color=color, linestyle=dash, linewidth=1.5, marker=marker,
                              markersize=FIXED_SIZE, label=label))
    ax_time.set_ylabel(MY_LABEL)
    ax_phase.set_xlabel(MX_LABEL)
    ax_phase.set_ylabel(MY_LABEL)
    fig.legend(handles=handles, loc="outside lower center", ncols=min(2, len(handles)),
               frameon=False, fontsize=9)
    set_title(fig, _comparison_title(runs, differ) if title is None else title)
    return Drawing(fig, (Table("traces", ("run_id", "panel", "x", "y"), rows),))


def _comparison_title(runs: Sequence[tuple[StoredRun, Traces]], differ: Sequence[str]) -> str:
    """"runs 5, 6" over the inputs they share (slopetui.sweeps.run_labels.INPUTS)."""
    first = runs[0][0]
    ids = ", ".join(str(r.id) for r, _ in runs)
    shared = [n for n in INPUTS if n not in differ]
    common = ", ".join(f"{symbol(n)}{EQUALS}{plain(value_text(getattr(first, n)))}" for n in shared)
    return f"runs {ids}\n{common}" if common else f"runs {ids}"
