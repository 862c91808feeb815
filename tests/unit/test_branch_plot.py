"""The bifurcation diagram of a stored continuation (slopetui.plots.branch_plot)."""

from __future__ import annotations

import re

import numpy as np
import pytest

from slopetui.plots.branch_plot import (
    BIFURCATION_STYLES,
    STABLE,
    UNSTABLE,
    amplitude_at,
    render_branch,
)

ANSI = re.compile(r"\x1b\[[0-9;]*m")


def subcritical_branch(n: int = 40) -> list[dict]:
    """A branch born unstable at a Hopf point k = 1.5 (amplitude 0), turning at a fold
    k = 1.2 and going on stable: it folds back, so it is not a function of k."""
    points = []
    for s in np.linspace(0.0, 1.0, n):
        points.append({"value": 1.2 + 1.875 * (s - 0.4) ** 2, "period": 20.0 + 10.0 * s,
                       "amplitude": 2.0 * s, "stable": bool(s > 0.4),
                       "leading_multiplier": [1.0, 0.0]})
    return points


FOLD = {"type": "fold", "value": 1.2, "period": 24.0, "multiplier": [1.0, 0.0]}


def plot_rows(text: str) -> list[str]:
    """The rows inside the plot frame."""
    return [m.group(1) for line in text.split("\n")
            if (m := re.match(r"^[ 0-9.e+-]*[┤│](.*)│$", line))]


def test_stable_unstable_and_fold_have_distinct_markers_without_colour():
    points = subcritical_branch()
    text = render_branch("k", points, [FOLD], title="continuation 1 in k", color=False)
    assert not ANSI.search(text)
    inside = "".join(plot_rows(text))
    fold = BIFURCATION_STYLES["fold"].marker
    assert len({STABLE.marker, UNSTABLE.marker, fold}) == 3
    assert STABLE.marker in inside and UNSTABLE.marker in inside and inside.count(fold) == 1
    n_stable = sum(p["stable"] for p in points)
    legend = text.rstrip("\n").split("\n")[-1]
    assert f"stable {n_stable}" in legend and f"unstable {len(points) - n_stable}" in legend
    assert "fold 1" in legend
    assert "m_y amplitude (peak to peak)" in text and "continuation 1 in k" in text


def test_colour_tells_the_parts_apart_too():
    text = render_branch("k", subcritical_branch(), [FOLD], color=True)
    assert ANSI.search(text)
    plain = ANSI.sub("", text)
    assert plain.count("F fold 1") == 1


@pytest.mark.parametrize(("width", "height"), [(80, 24), (40, 14), (140, 44)])
@pytest.mark.parametrize("color", [False, True])
def test_exactly_height_lines_of_at_most_width_columns(width, height, color):
    bifs = [FOLD, {"type": "torus", "value": 1.5, "period": 29.0, "multiplier": [0.6, 0.8]},
            {"type": "period-doubling", "value": 1.3, "period": 28.0, "multiplier": [-1, 0]}]
    text = render_branch("tau", subcritical_branch(), bifs, title="a title " * 30,
                         width=width, height=height, color=color)
    lines = text.split("\n")
    assert len(lines) == height
    assert max(len(ANSI.sub("", line)) for line in lines) <= width


@pytest.mark.parametrize("color", [False, True])
def test_no_points_is_a_message_of_the_same_size(color):
    text = render_branch("k", [], [], title="continuation 3 in k", width=60, height=20,
                         color=color)
    lines = text.split("\n")
    assert len(lines) == 20 and max(len(line) for line in lines) <= 60
    assert "no points yet" in text and "continuation 3 in k" in text


def test_the_fold_sits_on_the_branch_where_it_turns():
    points = subcritical_branch()
    values = np.array([p["value"] for p in points])
    amplitudes = np.array([p["amplitude"] for p in points])
    periods = np.array([p["period"] for p in points])
    # the turning point s = 0.4: amplitude 0.8, period 24; the points miss k = 1.2 itself
    assert amplitude_at(1.2, 24.0, values, amplitudes, periods) == pytest.approx(0.8, abs=0.06)
    # k = 1.5 is passed twice: the period picks the sheet (s = 0 unstable, s = 0.8 stable)
    assert amplitude_at(1.5, 20.0, values, amplitudes, periods) == pytest.approx(0.0, abs=0.06)
    assert amplitude_at(1.5, 28.0, values, amplitudes, periods) == pytest.approx(1.6, abs=0.06)


def test_unknown_types_and_unplottable_points_are_counted_not_dropped():
    points = [*subcritical_branch(10), {"value": float("nan"), "period": 1.0,
                                        "amplitude": 1.0, "stable": True}]
    text = render_branch("k", points, [{"type": "new-kind", "value": 1.3, "period": 25.0}],
                         color=False)
    assert "new-kind 1" in text and "1 not shown" in text
