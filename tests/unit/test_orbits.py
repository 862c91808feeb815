"""Periodic orbits, Floquet multipliers and continuation (core.orbit, core.shooting,
core.floquet, core.continuation, core.hopf_start), checked against theory and against
simulation, never against themselves."""

from __future__ import annotations

import math

import numpy as np
import pytest

from core.continuation import Branch, bifurcations, criticality, walk
from core.hopf_start import hopf_point
from core.orbit import Grid, OrbitError, PeriodMap
from core.orbit_seed import simulate_from
from core.params import Params
from core.periodic_orbit import find_orbit
from core.solve import SolverSettings, simulate
from core.stability import hopf_k


@pytest.fixture(scope="module")
def orbit10():
    """The stable period-1 orbit at k = 10, tau = 10 (the defaults)."""
    return find_orbit(Params(k=10.0, tau=10.0))


def test_the_two_unit_multipliers(orbit10):
    """The flow direction's multiplier is 1 to RK4's accuracy over a period; the
    translation of m_x is exactly neutral in the scheme (its multiplier is 1 exactly)."""
    m = orbit10.multipliers
    assert abs(m.flow - 1.0) < 1e-7
    assert m.translation == 1.0
    assert m.stable and abs(m.leading) < 0.9  # measured 0.6429
    assert orbit10.residual < 1e-10


def test_the_period_is_the_return_time_of_a_long_simulation(orbit10):
    """RK4 (core.rk4, the run kernel) from eq. 19 to t = 3000, same dt: the mean spacing of
    upward crossings of m_y = 0 over the last 100 periods equals the orbit's period to 1e-6
    relative (the orbit attracts by 0.64 a period, so 190 periods erase the transient)."""
    tr = simulate(Params(k=10.0, tau=10.0), SolverSettings(method="rk4", dt=0.01, t_end=3000.0,
                                                           window=1100.0, lyap=False))
    t, y = tr.window_t, tr.window[1]
    up = np.nonzero((y[:-1] < 0) & (y[1:] >= 0))[0]
    times = t[up] - y[up] * (t[up + 1] - t[up]) / (y[up + 1] - y[up])
    measured = (times[-1] - times[0]) / (len(times) - 1)
    assert len(times) > 100
    assert abs(measured / orbit10.period - 1) < 1e-6
    assert orbit10.maxima_per_period == 1


def test_the_hopf_point_with_noise_and_without():
    """Without noise the Hopf point is core.stability's exact one; with d = 1e-4 it moves
    to k = 6.14619 (the steady state carries variance, which couples to the delay)."""
    exact = hopf_k(10.0, Params().F1)
    assert abs(hopf_point(Params(tau=10.0, d=0.0)).value - exact) < 1e-9
    noisy = hopf_point(Params(tau=10.0, d=1e-4)).value
    assert 6.1460 < noisy < 6.1463 < exact


@pytest.mark.slow
def test_from_the_hopf_point_the_branch_is_subcritical_and_folds():
    """tau = 10: the cycles born at the Hopf point are unstable and exist below k_H; the
    branch turns at a fold of cycles near k = 1.2139 and comes back stable. A simulation
    started on the stable orbit just above the fold stays on it; just below, it falls to
    rest, as the multipliers say."""
    branch, _hopf = Branch.from_hopf(Params(tau=10.0), "k", 0.01, 1e-3, 0.02, 0.5)
    points = list(walk(branch, lambda pt: pt.value > 8.0, 300, 1e-7))
    assert criticality(points) == "subcritical"
    folds = [b for b in bifurcations(branch) if b.type == "fold"]
    assert len(folds) == 1
    fold = folds[0].value
    assert 1.2 < fold < 1.23
    assert all(b.type == "fold" for b in bifurcations(branch))  # no PD, no torus up to k = 8
    stable = [p for p in points if p.stable]
    above = min(stable, key=lambda p: p.value)
    assert above.value - fold < 0.05
    g = Grid.of(Params(tau=10.0), 0.01)
    for dk, stays in ((+0.003, True), (-0.003, False)):
        traj = simulate_from(Params(k=fold + dk, tau=10.0), g, above.z, 2000.0)
        late = float(np.ptp(traj[1, -2000:]))
        assert (late > 1.0) is stays, (dk, late)


@pytest.mark.slow
def test_the_branch_ends_at_the_exact_hopf_point_without_noise():
    """Continued down from the stable orbit at k = 10 (d = 0), the branch folds and
    returns unstable to vanish at the Hopf point: there within 2e-6 of the exact k_H."""
    p = Params(k=10.0, tau=10.0, d=0.0)
    o = find_orbit(p)
    shot = PeriodMap(p, o.grid).shoot(o.z, o.period)
    from core.shooting import Solution
    branch = Branch.from_orbit(p, o.grid, "k", Solution(o.z, o.period, shot, 0, 0.0, 0), -1.0,
                               0.05, 0.5)
    list(walk(branch, lambda pt: False, 300, 1e-7))
    ends = [b for b in bifurcations(branch) if b.type == "hopf"]
    assert len(ends) == 1
    assert abs(ends[0].value / hopf_k(10.0, p.F1) - 1) < 2e-6
    assert abs(ends[0].period / (2 * math.pi / math.sqrt(2 * hopf_k(10.0, p.F1) - p.F1 ** 2)) - 1) < 1e-6


def test_no_orbit_where_the_run_comes_to_rest():
    with pytest.raises(OrbitError, match="came to rest"):
        find_orbit(Params(k=4.0, tau=10.0), t_seed=1000.0)


def test_no_orbit_without_a_delay():
    with pytest.raises(OrbitError, match="tau must be > 0"):
        find_orbit(Params(k=10.0, tau=0.0))


def test_the_friction_hopf_point_inverts_the_friction_hopf_curve():
    """core.stability.hopf_friction at one tau lies on hopf_curve_friction (sampled
    densely: linear interpolation between samples is good to ~1e-5 here)."""
    from core.stability import hopf_curve_friction, hopf_friction
    p = Params(k=12.0)
    for name in ("a", "b", "c"):
        values, taus = hopf_curve_friction(p, name, 1600)
        for tau in (2.0, 10.0, 30.0):
            value, omega = hopf_friction(p.with_(tau=tau), name)
            assert value == pytest.approx(float(np.interp(tau, taus, values)), rel=2e-5, abs=1e-5)
            assert 0 < omega < math.sqrt(2 * p.k)


@pytest.mark.slow
def test_a_fold_in_a_friction_parameter_agrees_with_simulation():
    """(c, tau) plane, k = 12, tau = 10: the Hopf point in c is subcritical and the branch
    folds at c ~ 8.49 (sliding is stable at larger c, so the band lies above c_H). A
    simulation started on the stable orbit nearest the fold stays on it just below the
    fold, and falls to rest just above."""
    from core.fold_curve import fold_curve
    base = Params(k=12.0, tau=10.0)
    (point,) = fold_curve(base, [10.0], name="c")
    assert point.criticality == "subcritical" and point.fold is not None
    assert point.hopf < point.fold
    hopf = hopf_point(base.with_(c=point.hopf), "c")
    branch, _ = Branch.from_hopf(base.with_(c=hopf.value), "c", 0.01, 1e-3, 0.02, 0.5)
    points = list(walk(branch, lambda pt: pt.value < point.hopf - 1.0, 300, 1e-7))
    stable = [p for p in points if p.stable]
    nearest = max(stable, key=lambda p: p.value)
    assert point.fold - nearest.value < 0.1
    g = Grid.of(base, 0.01)
    for dc, stays in ((-0.02, True), (+0.02, False)):
        traj = simulate_from(base.with_(c=point.fold + dc), g, nearest.z, 3000.0)
        late = float(np.ptp(traj[1, -2000:]))
        assert (late > 0.5) is stays, (dc, late)
