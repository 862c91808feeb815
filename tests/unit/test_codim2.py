"""Codimension-two points between two points of a fold curve (core.codim2): a cusp where
the fold's quadratic coefficient changes sign (none claimed where the fold degenerates next
to the Hopf curve), and the kind of a multiplier crossing the circle, the fold's own two at
+1 left out."""

from __future__ import annotations

import numpy as np
import pytest

from core.codim2 import crossings, others, through_circle
from core.floquet import Multipliers
from core.fold_continuation import CurvePoint


def _point(k: float, curvature: float, others: list[complex], amplitude: float = 1.0
           ) -> CurvePoint:
    values = np.array([1.0 + 0j, 1.0 - 1e-9 + 0j, *others])  # the flow's, the fold's
    return CurvePoint(k, 10.0 - k, 11.0, amplitude, curvature,
                      Multipliers(values, 0, 1.0), 2)


def test_the_fold_s_two_multipliers_at_one_are_left_out():
    m = _point(1.0, 1.0, [0.5, -0.2]).multipliers
    assert sorted(others(m).real) == [-0.2, 0.5]
    assert sorted(others(m, "period-doubling").real) == [0.5, 1.0 - 1e-9]


def test_a_cusp_where_the_quadratic_coefficient_changes_sign():
    (c,) = crossings(_point(1.0, 2.0, [0.5]), _point(2.0, -2.0, [0.5]), largest=1.0)
    assert c.type == "cusp" and c.first == pytest.approx(1.5)


def test_no_cusp_is_claimed_where_the_fold_degenerates():
    (c,) = crossings(_point(1.0, 2e-3, [0.5], 0.03), _point(2.0, -2e-3, [0.5], 0.02),
                     largest=1.0)
    assert c.type == "undetermined" and "no cusp is claimed" in c.note


@pytest.mark.parametrize(("before", "after", "kind"), [
    (-0.98, -1.02, "fold-flip"),
    (0.6 + 0.78j, 0.62 + 0.8j, "fold-ns"),
    (0.98, 1.02, "resonance-1:1"),
])
def test_a_multiplier_through_the_circle_names_its_kind(before, after, kind):
    (c,) = crossings(_point(1.0, 1.0, [before]), _point(2.0, 1.0, [after]), largest=1.0)
    assert c.type == kind
    s = (abs(before) - 1) / ((abs(before) - 1) - (abs(after) - 1))
    assert c.first == pytest.approx(1.0 + s)


def test_a_multiplier_on_the_circle_within_the_margin_is_no_crossing():
    assert crossings(_point(1.0, 1.0, [-1.0 + 2e-6]), _point(2.0, 1.0, [-1.0 - 2e-6]),
                     largest=1.0) == []


def _torus(k: float, kappa: float, rest: list[complex]) -> CurvePoint:
    """A torus curve's point: the flow's multiplier, the pair exp(+-i theta) on the circle
    (cos theta = kappa, or a neutral saddle's mu, 1/mu past -1 or +1), and ``rest``."""
    if abs(kappa) <= 1:
        pair = [complex(kappa, np.sqrt(1 - kappa ** 2)), complex(kappa, -np.sqrt(1 - kappa ** 2))]
    else:
        mu = kappa + np.sign(kappa) * np.sqrt(kappa ** 2 - 1)
        pair = [complex(mu), complex(1 / mu)]
    values = np.array([1.0 + 0j, *pair, *rest])
    return CurvePoint(k, 10.0, 5.0, 2.0, float("nan"), Multipliers(values, 0, 1.0), 3, kappa)


def test_a_torus_s_own_pair_is_left_out_and_the_rest_watched():
    m = _torus(1.0, -0.5, [0.999 + 0.01j, 0.3]).multipliers
    assert sorted(others(m, "torus").real) == pytest.approx([0.3, 0.999])
    (c,) = crossings(_torus(1.0, -0.4, [-0.98]), _torus(2.0, -0.4, [-1.02]), what="torus")
    assert c.type == "flip-ns"


@pytest.mark.parametrize(("before", "after", "kind", "at"), [
    (-0.45, -0.55, "resonance-1:3", -0.5),
    (0.1, -0.3, "resonance-1:4", 0.0),
    (-0.99999, -1.00001, "resonance-1:2", -1.0),
    (0.9999, 1.0003, "resonance-1:1", 1.0),
])
def test_a_torus_curve_marks_the_strong_resonance_its_kappa_passes(before, after, kind, at):
    (c,) = crossings(_torus(1.0, before, []), _torus(2.0, after, []), what="torus")
    assert c.type == kind
    assert c.first == pytest.approx(1.0 + (before - at) / (before - after))


def test_the_torus_walk_ends_where_its_pair_meets_on_the_real_axis():
    from core.torus_continuation import TorusCurve

    curve = TorusCurve.__new__(TorusCurve)
    assert curve.ended(_torus(1.0, -0.9999999, [])) == ""
    assert "1:2 resonance" in curve.ended(_torus(1.0, -1.0001, []))
    assert "1:1 resonance" in curve.ended(_torus(1.0, 1.0001, []))


def test_a_slow_crossing_within_the_margin_next_to_it_is_found_once():
    """A pair creeping through the circle: within UNIT_MARGIN at the points either side
    of the crossing, clear two points before and after; one fold-ns (not one per member
    of the pair), where |mu| - 1 changes sign (points 2 and 3)."""
    moduli = [0.99996, 0.999995, 0.999998, 1.000003, 1.000006, 1.00004, 1.00005]
    pts = [_point(float(i), 1.0, [r * np.exp(2.1j), r * np.exp(-2.1j), 0.5])
           for i, r in enumerate(moduli)]
    found = [c for j in range(1, len(pts)) for c in through_circle(pts, j, "fold")]
    (c,) = found
    assert c.type == "fold-ns"
    assert c.first == pytest.approx(2.0 + 2e-6 / (2e-6 + 3e-6))


def test_a_crossing_that_wanders_within_the_margin_is_undetermined():
    moduli = [0.99996, 0.999995, 1.000004, 0.999996, 1.000003, 1.00004]
    pts = [_point(float(i), 1.0, [r * np.exp(2.1j), r * np.exp(-2.1j)])
           for i, r in enumerate(moduli)]
    (c,) = [c for j in range(1, len(pts)) for c in through_circle(pts, j, "fold")]
    assert c.type == "undetermined" and "fold-ns crossing" in c.note
    assert "3 times" in c.note and 0.0 < c.first < 5.0


@pytest.mark.parametrize(("u", "kind"), [(1e-7, "fold-ns"), (1e-5, "undetermined")])
def test_a_crossing_is_claimed_only_beyond_ten_uncertainties_on_both_sides(u, kind):
    moduli = [0.99996, 1.00005]
    pts = [_point(float(i), 1.0, [r * np.exp(2.1j), r * np.exp(-2.1j)])
           for i, r in enumerate(moduli)]
    (c,) = through_circle(pts, 1, "fold", lambda p, mu: u)
    assert c.type == kind
    if kind == "undetermined":
        assert "uncertain by 1.0e-05" in c.note and "not beyond 10" in c.note
