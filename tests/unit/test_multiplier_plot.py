"""A certified orbit's multipliers drawn against the unit circle (slopetui.plots.multiplier_plot)."""

from __future__ import annotations

from slopetui.plots.multiplier_plot import render_multipliers


def test_the_circle_and_each_multiplier_inside_or_outside_are_drawn():
    text = render_multipliers([[0.5, 0.0], [0.1, 0.3], [-1.5, 0.0]], width=60, height=20,
                              color=False)
    lines = text.splitlines()
    assert len(lines) == 20 and max(map(len, lines)) <= 60
    assert "2 inside" in text and "1 on or outside" in text and "|μ| = 1" in text
    assert "*" in text and "o" in text and "·" in text


def test_no_multipliers_is_said_not_drawn():
    assert "no multipliers" in render_multipliers([], width=60, height=20, color=False)
