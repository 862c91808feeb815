"""The terminal plots' ticks (round 1-2-5 numbers at the plot's size, no negative zero),
a run at rest drawn as a marked point, and "1 maximum" in a run's detail, on the
rendered text."""

from __future__ import annotations

import re

import numpy as np
import pytest

from core.classify import classify, maxima_words
from slopetui.plots.canvas import Series, render
from slopetui.plots.compare_plots import Overlay, render_compare_phase
from slopetui.plots.run_plots import FIXED_MARKER, render_lyapunov, render_phase_portrait
from slopetui.plots.ticks import axis_ticks, tick_label

NUMBER = re.compile(r"^-?(\d+(\.\d+)?|\d(\.\d+)?e-?\d+)$")


def y_labels(text: str) -> list[str]:
    """The labels left of the y axis' ticks (┤), top to bottom."""
    return [line.split("┤")[0].strip() for line in text.split("\n") if "┤" in line]


def x_labels(text: str) -> list[str]:
    """The labels under the x axis' ticks: the line under the frame's bottom (└)."""
    lines = text.split("\n")
    bottom = next(i for i, line in enumerate(lines) if line.lstrip().startswith("└"))
    return lines[bottom + 1].split()


def is_round(label: str) -> bool:
    """A 1, 2 or 5 times a power of ten multiple, written plainly: its significant digits
    (without sign, point and zeros) are one digit."""
    if "e" in label:
        label = label.split("e")[0]
    digits = label.lstrip("-").replace(".", "").strip("0")
    return len(digits) <= 2  # 1.5 = 15 x 0.1 at a step of 0.5


def plot(xs: np.ndarray, ys: np.ndarray, width: int = 60, height: int = 16, **options: bool) -> str:
    return render([Series(xs, ys, "braille", "green", line=True)], [], x_label="k", y_label="",
                  x_log=options.get("x_log", False), y_log=False, title="", width=width,
                  height=height, color=False)


@pytest.mark.parametrize("width", [30, 60, 80, 120])
def test_ticks_of_a_sweep_from_2_to_12_are_round_and_fit_the_width(width: int) -> None:
    # plotext's own: 2.000 3.111 ... (equal fractions of the range), e.g. 5.474, 8.947
    xs = np.linspace(2.0, 12.0, 50)
    text = plot(xs, np.sin(xs), width=width)
    xl, yl = x_labels(text), y_labels(text)
    assert len(xl) >= 3 and all(NUMBER.match(v) and is_round(v) for v in xl), xl
    steps = {round(b - a, 9) for a, b in zip(map(float, xl), map(float, xl[1:]), strict=False)}
    assert len(steps) == 1 and steps.pop() in (1.0, 2.0, 5.0), xl
    assert yl == ["0.5", "0.0", "-0.5"], yl
    assert max(map(len, text.split("\n"))) <= width


@pytest.mark.parametrize("lo, hi", [(-1.0, 1.0), (-0.3, 0.7), (-2.5e-8, 2.2e-8), (-1e-7, 3e-7)])
def test_no_tick_is_a_negative_zero(lo: float, hi: float) -> None:
    # plotext's own: -0.0000000015, -0.0000000093 ... around zero
    labels = y_labels(plot(np.linspace(2.0, 12.0, 50), np.linspace(lo, hi, 50)))
    assert labels and all(NUMBER.match(v) and is_round(v) for v in labels), labels
    assert not any(re.fullmatch(r"-0(\.0*)?", v) for v in labels), labels
    assert sum(1 for v in labels if float(v) == 0.0) == 1


def test_tick_labels_carry_the_decimals_of_their_step() -> None:
    assert [tick_label(v, 0.05) for v in (0.0, 0.05, -0.1, 1.25)] == ["0.00", "0.05", "-0.10", "1.25"]
    assert [tick_label(v, 50.0) for v in (-0.0, 150.0)] == ["0", "150"]
    assert tick_label(-1e-7, 1e-7) == "-1e-7" and tick_label(2e6, 1e6) == "2e6"
    assert tick_label(-1e-12, 0.1) == "0.0"  # a rounding error below zero is zero


def test_a_log_axis_ticks_decades() -> None:
    # plotext's own: 0.1, 0.7, 4.5, 29.9, 200.0 (equal steps of the logarithm)
    t = np.linspace(0.0, 200.0, 2001)
    text = render_lyapunov(t, np.sin(t) / (1.0 + t), width=80, height=14, color=False)
    assert x_labels(text) == ["0.1", "1", "10", "100"]
    ticks, labels = axis_ticks(3.0, 40.0, log=True, length=60, label_room=True)
    assert labels == ["5", "10", "20"] and ticks == [5.0, 10.0, 20.0]


def test_a_run_at_rest_is_a_marked_point_named_in_the_legend() -> None:
    # it was a message ("The orbit is a fixed point ...") with no plot
    t = np.linspace(100.0, 200.0, 10_001)
    text = render_phase_portrait(t, 0.1 * t, np.full_like(t, 0.1), width=80, height=20, color=False)
    lines = text.split("\n")
    assert len(lines) == 20
    assert sum(line.count(FIXED_MARKER) for line in lines) == 2  # the point and its legend
    assert f"{FIXED_MARKER} a fixed point: m_y = 0.1" in lines[-2]
    assert "vary by less than 1e-06" in lines[-1]
    assert x_labels(text) == ["-1.0", "-0.8", "-0.6", "-0.4", "-0.2", "0.0", "0.2", "0.4", "0.6",
                              "0.8", "1.0"]  # a frame of ±1 around the point


def test_a_run_at_rest_among_orbits_is_a_mark_of_its_own() -> None:
    # it was its round-off drawn as a line: one braille dot, and the legend said nothing
    t = np.linspace(100.0, 200.0, 10_001)
    cycle = Overlay("run 5: k 12 (oscillatory)", t, 0.1 * t - np.cos(2 * np.pi * 0.2 * t) / (2 * np.pi * 0.2),
                    0.1 + np.sin(2 * np.pi * 0.2 * t), 0.2)
    rest = Overlay("run 7: k 8 (sliding)", t, 0.1 * t, np.full_like(t, 0.1))
    text = render_compare_phase([rest, cycle], width=80, height=20, color=False)
    canvas = "\n".join(text.split("\n")[:-4])
    assert canvas.count(FIXED_MARKER) == 1
    assert f"{FIXED_MARKER} run 7: k 8 (sliding): a fixed point" in text.split("\n")[-1]


def test_one_maximum_is_singular() -> None:
    assert [maxima_words(n) for n in (0, 1, 2)] == ["0 maxima", "1 maximum", "2 maxima"]
    t = np.arange(0.0, 400.0, 0.01)
    y = np.sin(2 * np.pi * t / 5.0)
    s = classify(t, np.vstack([np.cumsum(y) * 0.01, y, np.zeros_like(t), np.zeros_like(t), np.zeros_like(t)]))
    assert s.regime == "oscillatory" and s.detail.startswith("period-1, 1 maximum"), s.detail
