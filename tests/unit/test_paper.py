"""Held to the paper: Fig. 4A, Fig. 7, and Euler against RK4 on the attractor.

These run the paper's horizon t_end = 1e5 with the paper's Euler scheme (dt = 1e-3),
about 0.7 s per point.
"""

from __future__ import annotations

import pytest

from core.params import Params, sliding_branches
from core.point import run_point
from core.solve import SolverSettings

#: ~7 s in all: out of the fast loop (`pytest -m "not slow"`), in the full suite.
pytestmark = pytest.mark.slow

PAPER = SolverSettings(method="euler", lyap=False)   # dt 1e-3, t_end 1e5, window 1000


@pytest.mark.parametrize(
    "k,regime,maxima",
    [(3.0, "sliding", 0), (5.0, "sliding", 0),
     (7.0, "oscillatory", 1), (10.0, "oscillatory", 1), (16.0, "oscillatory", 1),
     (18.0, "oscillatory", 2), (20.0, "oscillatory", 2), (24.0, "oscillatory", 3)],
)
def test_fig_4a_orbits_return_after_one_basic_period(k, regime, maxima):
    # The paper calls k >= 17 "complex" (period doubling). The orbits there return after
    # one basic period (10.3-10.4 at tau = 10, 10.62 at k = 7) with 2 or 3 maxima in it
    r = run_point(Params(k=k, tau=10.0, delta=0.1), PAPER)
    assert r.summary.regime == regime, r.summary
    assert r.summary.maxima_per_period == maxima, r.summary
    if regime == "oscillatory":
        assert r.summary.period_count == 1 and 10.2 < r.summary.period < 10.7, r.summary


@pytest.mark.parametrize("tau", [0.2, 20.0])
def test_fig_7_low_a_runs_away_to_the_fast_branch(tau):
    # Euler at dt = 1e-3 blows up on the branch (stiffness ~2900 > 2/dt); the stiff-safe
    # scheme rests there: a runaway of the model, not a divergence
    p = Params(a=0.035, k=12.0, tau=tau, delta=0.1)
    r = run_point(p, PAPER)
    assert r.summary.regime == "unstable" and r.summary.attractor == "fast-branch", r.summary
    assert "stiff-fallback" in r.summary.flags and r.t_blowup is not None
    m_y = r.trajectory.window[1, -1]
    assert m_y == pytest.approx(max(sliding_branches(p)), rel=1e-6)


def test_fig_7_near_fixed_point_and_small_tau_slides():
    r = run_point(Params(a=0.035, k=12.0, tau=0.2, delta=1e-6), PAPER)
    assert r.summary.regime == "sliding"
    # at the fixed point m_y = 0, not on the faster branch at m_y = 204.6 that low a opens
    # (core.params.sliding_branches), where the runs from delta = 0.1 go before blowing up
    assert abs(r.summary.drift) < 1e-3


def test_euler_and_rk4_agree_on_the_attractor():
    p = Params(k=10.0, tau=10.0)
    euler = run_point(p, PAPER).summary
    rk4 = run_point(p, SolverSettings(method="rk4", lyap=False)).summary
    assert euler.regime == rk4.regime == "oscillatory"
    assert euler.maxima_per_period == rk4.maxima_per_period == 1
    # Euler is first order at dt = 1e-3: the numerics note measured ~1e-3 errors
    assert euler.amplitude == pytest.approx(rk4.amplitude, rel=2e-3)
    assert euler.period == pytest.approx(rk4.period, rel=5e-4)
