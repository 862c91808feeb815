"""The torus (Neimark-Sacker) bifurcation continued as a curve (core.torus_continuation),
checked apart from its bordered system: at its points a freshly corrected orbit's Floquet
multipliers (ARPACK on the monodromy) have a pair on the unit circle, the pair's |mu| - 1
changes sign across the point at fixed tau, and the one-parameter continuation at another
tau finds its torus where the curve passes.

The 2-slip branch at tau = 10 (d = 1e-4) gains stability through a torus at k = 5.2567
whose pair sits 4.7e-4 off the real axis, next to the 1:2 resonance; the 3-slip branch's
torus at k = 9.8623 has a second pair 1.4e-3 from the crossing one, next to 1:3.
"""

from __future__ import annotations

import functools

import numpy as np
import pytest

from core.curve_start import CurveSpec, start
from core.floquet import multipliers
from core.orbit import Grid, PeriodMap
from core.params import Params
from core.shooting import correct
from core.torus_continuation import first_torus

pytestmark = pytest.mark.computation  # only computes: beside the slow tiers (tests/xdist_plan.py)


@functools.cache
def _curve(n: int, to2: float, points: int):
    """The torus curve of the n-slip branch from tau = 10 to ``to2``: its saved points and
    the walk."""
    walk = start(CurveSpec(Params(tau=10.0), "k", "tau", "ns", 0.01, to2, points, 0.25, n,
                           branch_end=25.0))
    saved = []
    while (p := walk.step()) is not None:
        saved.append(p)
    return saved, walk


def _pair_off_circle(k: float, tau: float, state: np.ndarray) -> float:
    """|mu| - 1 of the multiplier nearest the circle (but the flow's) of the orbit at (k,
    tau) corrected from a curve point's state, on the curve's grid (N = 1000)."""
    n_delay = int(state[0])
    n = Grid(1.0, n_delay).size
    y = state[3:3 + n + 3]
    pm = PeriodMap(Params(tau=tau, k=k), Grid(tau / n_delay, n_delay))
    z, period = y[:n], float(y[n])
    sol = correct(pm, z, period, z, pm.shoot(z, period).d_dT)
    moduli = np.abs(multipliers(pm, sol.shot, 8).nontrivial)
    return float(moduli[np.argmin(np.abs(moduli - 1.0))] - 1.0)


def test_the_2_slip_torus_curve_keeps_a_pair_on_the_circle_and_crosses_it_there():
    saved, walk = _curve(2, 10.5, 20)
    assert walk.end == "reached tau = 10.5"
    assert abs(saved[0].first - 5.2567) < 1e-3 and saved[0].second == 10.0
    last = saved[-1]
    assert last.second == 10.5 and 4.9 < last.first < 4.95  # the torus moves to lower k
    assert abs(_pair_off_circle(last.first, 10.5, last.state)) < 1e-9
    # across it at fixed tau the pair leaves the circle: outside below, inside above (the
    # 2-slip orbits gain stability with k)
    assert _pair_off_circle(last.first - 1e-3, 10.5, last.state) > 1e-7
    assert _pair_off_circle(last.first + 1e-3, 10.5, last.state) < -1e-7
    # next to the 1:2 resonance the whole way, not through it
    assert all(-1.0 < p.kappa < -0.9999998 for p in walk.curve.points)
    assert [c.type for c in walk.found()] == []


def test_the_one_parameter_continuation_finds_the_torus_where_the_curve_passes():
    saved, _ = _curve(2, 10.5, 20)
    n_delay = int(saved[-1].state[0])  # 1050: chosen for tau = 10.5 at dt = 0.01
    assert n_delay == 1050
    _, ns, _ = first_torus(Params(tau=10.5), "k", 10.5 / n_delay, 25.0, hopf_branch=2)
    # the one-parameter location carries the near-defective pair's ARPACK error (5e-9 in
    # |mu| there): 4.7e-6 apart in k, where the curve's point has |mu| - 1 = -3e-11
    assert ns.type == "torus" and abs(ns.value - saved[-1].first) < 2e-5


def test_a_torus_curve_asked_downwards_goes_down():
    saved, walk = _curve(2, 9.9, 4)
    assert walk.end == "reached tau = 9.9"
    seconds = [p.second for p in saved]
    assert seconds == sorted(seconds, reverse=True) and seconds[-1] == 9.9
    assert int(saved[0].state[0]) == 1000  # no larger tau to choose the grid for


def test_the_3_slip_torus_curve_beside_a_second_pair_near_the_circle():
    # downwards: the grid is the branch's at dt = 0.01. (Upwards, to tau = 10.1, it is
    # chosen for 10.1, dt = 10 / 1010, and the start moves to k = 9.8713: this slow
    # crossing, d|mu|/dk ~ 1.3e-4, lies within ~2e-2 in k of the RK4 scheme's own.)
    saved, walk = _curve(3, 9.9, 5)
    assert abs(saved[0].first - 9.8623) < 1e-3
    for p in (saved[1], saved[-1]):
        assert abs(_pair_off_circle(p.first, p.second, p.state)) < 1e-9
    # its kappa near cos(2 pi / 3): no strong resonance passed on this stretch
    assert [c.type for c in walk.found()] == []
