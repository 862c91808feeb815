"""Whether a multiplier really crossed the unit circle (core.multiplier_crossing): which
multiplier crossed, the verdict against its uncertainty, and the located point, on
multipliers whose crossing is known by construction."""

from __future__ import annotations

import math

import numpy as np
import pytest

from core.floquet import Multipliers
from core.multiplier_crossing import (
    CLEAR,
    LOCATE_TOL,
    Corrector,
    Orbit,
    crossing_multiplier,
    halved,
    judge,
    resonance,
)
from core.orbit import Grid, OrbitError


def _m(*others: complex) -> Multipliers:
    """Multipliers with the flow's first (index 0) and the given nontrivial ones."""
    return Multipliers(np.array([1.0 + 0j, *others]), 0, 1.0)


def test_the_crossing_multiplier_is_followed_not_guessed():
    """Beside a fold (tau = 10, N = 2 branch, k = 3.038 -> 2.948) the multiplier through +1
    is 1.147 -> 0.979, while one at -1.00043 -> -1.00047 stays outside: the nearest to the
    circle at b is the latter, which the interval's old reading took for a period
    doubling at k = 3.95, outside the interval."""
    a = _m(-1.615701, 1.146970, -1.000428, -0.660614 + 0.068943j, -0.660614 - 0.068943j)
    b = _m(-1.457204, -1.000471, 0.978504, -0.623297 + 0.044281j, -0.623297 - 0.044281j)
    mu_a, mu_b = crossing_multiplier(a, b)
    assert mu_a == pytest.approx(1.146970) and mu_b == pytest.approx(0.978504)
    assert crossing_multiplier(a, a) is None


def _line(p0: float, slope: float, angle: float) -> Corrector:
    """A corrector whose orbit at p carries a multiplier of modulus 1 + slope (p - p0) at
    a fixed angle (the state is the parameter itself)."""
    def mu(p: float) -> complex:
        return (1.0 + slope * (p - p0)) * complex(math.cos(angle), math.sin(angle))

    def at(value: float, z: np.ndarray, period: float) -> Orbit:
        m = mu(value)
        return Orbit(value, np.array([value]), 2.0 + value, Grid(0.01, 1),
                     _m(m, m.conjugate(), 0.3))
    return at


@pytest.mark.parametrize(("angle", "kind"), [(math.pi, "period-doubling"), (2.0, "torus"),
                                             (0.0, "branch-point")])
def test_a_clear_crossing_is_located_to_the_tolerance(angle, kind):
    p0 = 1.234567891
    at = _line(p0, 0.05, angle)
    a, b = at(1.0, None, 0.0), at(1.5, None, 0.0)
    v = judge(at, [a], [b], lambda o, m: 1e-8)
    assert v is not None and v.kind == kind
    assert abs(v.value - p0) < LOCATE_TOL
    assert abs(abs(v.multiplier) - 1) < 0.05 * LOCATE_TOL
    assert v.period == pytest.approx(2.0 + v.value)


def test_a_crossing_within_the_uncertainty_is_undetermined():
    """|mu| - 1 = -5e-7 and +8.8e-7 on the two sides, uncertain by 2.7e-6 (the N = 2 branch
    at tau = 10 between k = 8.84 and 9.34): undetermined, with the figures, and no orbit
    corrected to locate it."""
    def at(value: float, z: np.ndarray, period: float) -> Orbit:
        raise AssertionError("an undetermined crossing is not located")

    a = Orbit(8.84, np.zeros(1), 5.27, Grid(0.01, 1), _m(-0.9999995, 0.73))
    b = Orbit(9.34, np.zeros(1), 5.26, Grid(0.01, 1), _m(-1.00000088, 0.73))
    v = judge(at, [a], [b], lambda o, m: 2.7e-6 if o is a else 2.9e-6)
    assert v.kind == "undetermined"
    assert "-5.0e-07 at 8.84 (uncertain by 2.7e-06)" in v.reason and "+8.8e-07" in v.reason
    assert 8.84 < v.value < 9.34
    # the same figures clear of CLEAR uncertainties are a real crossing
    at = _line(9.0, 1e-3, math.pi)
    v = judge(at, [at(8.84, None, 0.0)], [at(9.34, None, 0.0)], lambda o, m: 1e-6 / CLEAR)
    assert v.kind == "period-doubling" and abs(v.value - 9.0) < LOCATE_TOL


def test_a_complex_pair_within_its_uncertainty_of_the_real_axis_is_not_a_torus():
    at = _line(1.2, 0.05, math.pi - 1e-7)
    v = judge(at, [at(1.0, None, 0.0)], [at(1.5, None, 0.0)], lambda o, m: 1e-7)
    assert v.kind == "period-doubling"


def test_resonances_are_named():
    assert "1:2" in resonance(complex(-1.0, 4.7e-4))
    assert "1:3" in resonance(complex(math.cos(2 * math.pi / 3), math.sin(2 * math.pi / 3)))
    assert "1:4" in resonance(1j)
    assert resonance(complex(math.cos(2.0), math.sin(2.0))) == ""
    assert resonance(-1.0 + 0j) == ""


def test_the_halved_state_samples_the_same_history():
    """A smooth history on N = 50 samples, refined to dt / 2: the even samples are the old
    ones, the odd ones the function's values to the spline's accuracy."""
    g = Grid(0.02, 50)
    t = -np.arange(1, 51) * g.dt
    z = np.concatenate(([math.cos(0.0), 0.1, 0.2, 0.3], np.sin(t), np.cos(t)))
    z2, g2 = halved(z, g)
    assert g2 == Grid(0.01, 100) and z2.size == g2.size
    t2 = -np.arange(1, 101) * g2.dt
    assert np.allclose(z2[:4], z[:4])
    assert np.allclose(z2[4 + 1:104:2], np.sin(t))
    assert np.abs(z2[4:104] - np.sin(t2)).max() < 1e-7
    assert np.abs(z2[104:] - np.cos(t2)).max() < 1e-7


def test_a_side_too_near_the_circle_is_judged_a_point_farther():
    """The point after a real crossing can land next to it (b at tau = 2: +0.02 at 6e-5
    past the period doubling, uncertain by 1.9e-3): the side is judged at the next point
    (up to WIDEN), and the crossing located between the clear ends; a side whose next
    point goes back across the circle stays undetermined."""
    at = _line(1.2, 0.05, math.pi)
    side_a = [at(1.0, None, 0.0)]
    near, farther = at(1.2004, None, 0.0), at(1.3, None, 0.0)  # |mu| - 1 = 2e-5, 5e-3
    v = judge(at, side_a, [near, farther], lambda o, m: 1e-5)
    assert v.kind == "period-doubling" and abs(v.value - 1.2) < LOCATE_TOL
    assert "+5.0e-03 at 1.3" in v.reason
    assert judge(at, side_a, [near], lambda o, m: 1e-5).kind == "undetermined"
    back = at(1.1, None, 0.0)  # inside again
    assert judge(at, side_a, [near, back], lambda o, m: 1e-5).kind == "undetermined"


def test_an_uncertainty_that_cannot_be_measured_leaves_the_crossing_undetermined():
    at = _line(1.2, 0.05, math.pi)

    def error(o: Orbit, mu: complex) -> float:
        raise OrbitError("Newton did not converge")

    v = judge(at, [at(1.0, None, 0.0)], [at(1.5, None, 0.0)], error)
    assert v.kind == "undetermined" and "Newton did not converge" in v.reason
