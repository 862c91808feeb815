"""A curve drawn in its plane names what it is a curve of: a torus curve's points and its
strong resonances carry their own legend."""

from __future__ import annotations

from slopetui.plots.curve_plot import render_curve


def test_a_torus_curve_and_its_resonance_are_named_in_the_legend():
    points = [{"k": 9.86 - 0.2 * i, "tau": 10.0 + 0.5 * i, "period": 3.5} for i in range(8)]
    found = [{"type": "resonance-1:3", "k": 9.2, "tau": 11.6, "period": 3.9, "note": ""}]
    text = render_curve("k", "tau", points, found, title="curve 3", color=False, kind="ns")
    lines = text.splitlines()
    assert len(lines) == 24 and all(len(line) <= 80 for line in lines)
    assert "torus 8" in text and "resonance-1:3 1" in text
    assert "fold of cycles" not in text
