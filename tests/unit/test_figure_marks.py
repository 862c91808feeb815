"""What a referee checks on a run's figure: the time axis' offset text never overprints
its label, and a run at rest is a point one can see in the phase portrait."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from core.classify import Summary, power_spectrum
from core.lyapunov import LyapunovEstimate
from slopetui.figures import run_drawing
from slopetui.sweeps.recompute import Traces
from tests.unit.test_figures import stored_run


def traces(t0: float, t1: float, *, f: float = 0.2, amp: float = 1.0, n: int = 5001) -> Traces:
    """A cycle of frequency f over the window t0..t1 (amp 0: a run at rest at m_y = 0.1,
    m_x a ramp of slope 0.1)."""
    t = np.linspace(t0, t1, n)
    m_y = 0.1 + amp * np.sin(2 * np.pi * f * t)
    m_x = 0.1 * t - amp / (2 * np.pi * f) * np.cos(2 * np.pi * f * t)
    freq, power = power_spectrum(t, m_y)
    lam_t = np.linspace(0.0, t1, 501)
    regime = "oscillatory" if amp else "sliding"
    return Traces(t, m_x, m_y, freq, power, lam_t, np.sin(lam_t) / (1.0 + lam_t),
                  Summary(regime, "", 2 * amp, 1 / f, 1, frequency=f if amp else float("nan")),
                  LyapunovEstimate(0.0008, 0.0009, 100.0, 10), "rk4 map at dt = 0.01")


def drawn(figure: Figure) -> Any:
    """The figure laid out and drawn by Agg: its renderer."""
    canvas = FigureCanvasAgg(figure)
    canvas.draw()
    return canvas.get_renderer()


def long_runs(**first: Any) -> list[tuple[Any, Traces]]:
    """Two runs of t_end 1e5 whose last 10 periods (50 time units) end at t = 100 000,
    where matplotlib labels the ticks -50..0 with an offset "+1e5"."""
    return [(stored_run(5, t_end=1e5, window=1000.0), traces(99_000.0, 100_000.0, **first)),
            (stored_run(6, k=14.0, t_end=1e5, window=1000.0), traces(99_000.0, 100_000.0, f=0.3, amp=0.5))]


@pytest.mark.parametrize("runs", [long_runs()[:1], long_runs()], ids=["one run", "comparison"])
def test_the_time_axis_offset_does_not_overprint_its_label(runs: list[tuple[Any, Traces]]) -> None:
    figure = run_drawing(runs).figure
    renderer = drawn(figure)
    ax = figure.axes[0]  # the time series
    offset, label = ax.xaxis.get_offset_text(), ax.xaxis.label
    if offset.get_text():
        assert not offset.get_window_extent(renderer).overlaps(label.get_window_extent(renderer))
    # the origin is in the label, and the ticks read as the time since it
    assert label.get_text().startswith("t − 100000 (model time units): the last 10 periods")
    ticks = [float(t.get_text().replace("−", "-")) for t in ax.get_xticklabels() if t.get_text()]
    assert min(ticks) >= -60 and max(ticks) <= 10
    xs = np.concatenate([line.get_xdata() for line in ax.get_lines()])
    assert xs.max() == pytest.approx(0.0) and xs.min() == pytest.approx(-50.0, abs=0.5)


def test_a_short_time_axis_keeps_its_plain_label() -> None:
    figure = run_drawing([(stored_run(5), traces(100.0, 200.0))]).figure
    drawn(figure)
    ax = figure.axes[0]
    assert ax.xaxis.label.get_text().startswith("t (model time units): the last 10 periods")
    assert ax.xaxis.get_offset_text().get_text() == ""


def _marker_pixels(figure: Figure, ax_index: int, renderer: Any) -> list[float]:
    """The area (pixels²) each line of an axes covers once drawn: its window extent."""
    ax = figure.axes[ax_index]
    return [line.get_window_extent(renderer).width * line.get_window_extent(renderer).height
            for line in ax.get_lines()]


def test_a_run_at_rest_is_a_marked_point_named_in_the_comparisons_legend() -> None:
    runs = [(stored_run(5), traces(100.0, 200.0)),
            (stored_run(7, k=8.0, regime="sliding"), traces(100.0, 200.0, amp=0.0))]
    figure = run_drawing(runs).figure
    renderer = drawn(figure)
    phase = figure.axes[1]
    rest = [line for line in phase.get_lines() if line.get_color() == "#D55E00"]  # the second run's colour
    assert len(rest) == 1 and rest[0].get_marker() == "o" and rest[0].get_markersize() >= 5
    box = rest[0].get_window_extent(renderer)
    assert box.width >= 5 and box.height >= 5  # pixels: a visible point, not a zero-length line
    assert list(rest[0].get_xydata()[0]) == pytest.approx([0.0, 0.1])
    legend = figure.legends[0]
    texts = [t.get_text() for t in legend.get_texts()]
    assert texts[1] == "run 7: k 8 (sliding): a fixed point, marked"
    assert legend.legend_handles[1].get_marker() == "o"
    assert legend.legend_handles[0].get_marker() in ("none", "None")  # the orbit: a line


def test_a_single_run_at_rest_names_its_marker_in_the_legend() -> None:
    figure = run_drawing([(stored_run(2, regime="sliding"), traces(100.0, 200.0, amp=0.0))]).figure
    drawn(figure)
    legend = figure.axes[1].get_legend()
    assert legend.legend_handles[0].get_marker() == "o"
    assert legend.get_texts()[0].get_text() == "a fixed point: $m_y$ = 0.1"
