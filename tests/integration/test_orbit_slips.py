"""The equally spaced n-slip orbits at large k (core.orbit_seed.n_slip_seed), checked by
the run kernel (core.rk4 through core.solve, not the shooting's core.period_map) started
from the orbit's state, and by a finer step."""

from __future__ import annotations

import math

import numpy as np
import pytest

from core.certify import STABLE_MARGIN, orbit_verdict
from core.history import CarriedState
from core.orbit import Grid
from core.orbit_seed import simulate as simulate_orbit_scheme
from core.orbit_seed import simulate_from, slip_onsets, state_at, state_from_carried
from core.params import Params
from core.periodic_orbit import Orbit, find_orbit
from core.point import run_point
from core.solve import SolverSettings, simulate


def carried(o: Orbit) -> CarriedState:
    """The orbit's state as a run's final state (m_x(0) = 0; m_x at -tau + j dt)."""
    n = o.grid.n_delay
    xi = o.z[4:4 + n]                      # m_x(-j dt) - m_x(0), j = 1..N
    return CarriedState(o.params.tau, o.grid.dt, np.concatenate(([0.0], o.z[:4])), xi[::-1].copy())


def onsets(t: np.ndarray, y: np.ndarray) -> np.ndarray:
    level = 0.5 * (y.min() + y.max())
    up = np.nonzero((y[:-1] < level) & (y[1:] >= level))[0]
    return t[up] + (level - y[up]) * (t[up + 1] - t[up]) / (y[up + 1] - y[up])


@pytest.fixture(scope="module")
def three_slip():
    """The target: k = 18, tau = 10, delta = 1e-6 (the run from eq. 19 reaches
    three unequally spaced slips per T_1 = 10.38; the old code's Newton did not converge)."""
    return find_orbit(Params(k=18.0, tau=10.0, delta=1e-6))


def test_the_three_slip_orbit_and_its_multipliers(three_slip):
    o = three_slip
    assert o.slips == 3 and o.maxima_per_period == 1
    assert abs(o.period - 3.4608) < 1e-4          # measured 3.460861
    m = o.multipliers
    # the flow multiplier is 2.1e-7 from 1 here (1e-9 at k = 10): within UNIT_TOL
    assert abs(m.flow - 1.0) < 1e-6 and abs(m.translation - 1.0) < 1e-12
    # 2 (n - 1) = 4 multipliers near the circle: near the cube roots of unity (over three
    # periods, T_1, they are near 1), measured |mu| 0.999991 (pair) and 0.999896 (pair)
    near = [v for v in m.nontrivial if abs(abs(v) - 1) < 1e-3]
    assert len(near) == 4
    for v in near:
        assert abs(v ** 3 - 1) < 1e-3
    assert all(abs(v) < 0.9 for v in m.nontrivial if abs(abs(v) - 1) >= 1e-3)


def test_the_run_kernel_from_the_orbit_stays_on_it(three_slip):
    """core.rk4 from the orbit's state for 2000 time units: every slip gap is the orbit's
    period (within 1e-5: the near-neutral directions are excited only by the start's
    interpolation), so the slips stay equally spaced, as the referee's 2e6 runs end."""
    o = three_slip
    c = carried(o)
    tr = simulate(o.params, SolverSettings(method="rk4", dt=o.grid.dt, t_end=2000.0,
                                           window=500.0, lyap=False, history=c.name), c)
    gaps = np.diff(onsets(tr.window_t, tr.window[1]))
    assert len(gaps) > 100
    assert np.abs(gaps / o.period - 1).max() < 1e-5


def test_a_run_on_the_three_slip_orbit_is_undetermined_not_unstable(three_slip):
    """Its pair at |mu| = 0.9999913 lies within core.certify.STABLE_MARGIN of the circle:
    the run's certificate claims neither stability nor instability (it used to say "the
    orbit is not stable" of an orbit every long run approaches)."""
    o = three_slip
    c = carried(o)
    r = run_point(o.params, SolverSettings(method="rk4", dt=o.grid.dt, t_end=2000.0,
                                           window=500.0, history=c.name), c)
    cert = r.certificate
    assert not cert.certified
    assert cert.text.startswith("the orbit's stability is undetermined: a multiplier within "
                                f"{STABLE_MARGIN:g} of the unit circle"), cert.text
    assert "unstable" not in cert.text and "not stable" not in cert.text
    assert abs(cert.period / o.period - 1) < 1e-8           # the orbit, at period T_1 / 3
    assert cert.slips == o.maxima_per_period == 1
    top = max(abs(m) for m in cert.multipliers)
    assert 1 - STABLE_MARGIN <= top < 1                    # measured 0.9999913
    assert orbit_verdict(top) == "marginal"


def test_a_finer_step_gives_the_same_period(three_slip):
    fine = find_orbit(Params(k=18.0, tau=10.0, delta=1e-6), dt=0.005, slips=3)
    assert abs(fine.period / three_slip.period - 1) < 1e-7


def test_slips_from_the_single_slip_orbit():
    """delta = 1 at k = 18 reaches the single-slip orbit (period 10.3817): --slips 2 and 3
    build the seeds from its one cycle, with no multi-slip transient at all."""
    p = Params(k=18.0, tau=10.0, delta=1.0)
    one = find_orbit(p)
    assert one.slips == 1 and abs(one.period - 10.3817) < 1e-3
    two = find_orbit(p, slips=2)
    three = find_orbit(p, slips=3)
    assert abs(two.period - 5.190881) < 1e-5 and two.slips == 2
    assert abs(three.period - 3.460861) < 1e-5


def test_four_and_five_slips():
    """The 4-slip orbit exists at k = 18 (period 2.59654, 2 (4 - 1) = 6 multipliers within
    2e-4 of the circle, all inside); the 5-slip one too, but unstable (|mu| 1.0017)."""
    p = Params(k=18.0, tau=10.0, delta=1e-6)
    four = find_orbit(p, slips=4)
    assert abs(four.period - 2.596538) < 1e-5
    near = [v for v in four.multipliers.nontrivial if abs(abs(v) - 1) < 1e-3]
    assert len(near) == 6 and max(abs(v) for v in near) < 1.0
    five = find_orbit(p, slips=5)
    assert abs(five.period - 2.078871) < 1e-5 and not five.stable


def test_a_run_state_seeds_the_orbit(three_slip):
    """A run's final state (Euler dt 1e-3, the paper's scheme) seeds the simulation."""
    p = Params(k=18.0, tau=10.0, delta=1e-6)
    tr = simulate(p, SolverSettings(method="euler", dt=1e-3, t_end=300.0, lyap=False))
    z = state_from_carried(tr.final, Grid.of(p, 0.01))
    o = find_orbit(p, start=z)
    assert o.slips in (2, 3)
    assert abs(o.period * o.slips / (three_slip.period * 3) - 1) < 2e-3


def test_the_run_approaches_it_at_the_leading_multipliers_rate(three_slip):
    """The referee's long run, with the orbit's own scheme (RK4, dt 0.01) from eq. 19 to
    t = 2e6 (13 s): the largest distance of the run's state at its last 30 slip onsets
    from the orbit's at its onset falls from 0.107 (t = 1e6) to 0.0093 (2e6), a rate of
    -2.44e-6/t, against ln|mu| / T = ln 0.9999913 / 3.46086 = -2.51e-6/t from Arnoldi: an
    independent check of the leading multiplier. (At t = 1e5, the plane's t_end, the
    distance is 1.25 and was still growing from 0.80 at 5e4.)"""
    o = three_slip
    p, g = o.params, o.grid
    w = g.weights
    ring = simulate_from(p, g, o.z, 3 * o.period + 1)
    z_orbit, _ = state_at(ring, g, float(slip_onsets(ring, g, 2 * o.period)[-1]))

    def distance(traj: np.ndarray, end: float) -> float:
        """The largest distance from the orbit at the last 30 slip onsets before end."""
        on = slip_onsets(traj, g, 300.0)
        far = 0.0
        for t in on[on < end][-30:]:
            d = state_at(traj, g, float(t))[0] - z_orbit
            far = max(far, math.sqrt(float(np.dot(d * w, d))))
        return far

    chunk = 100000.0                       # 20 chunks, each from the last one's state
    traj = simulate_orbit_scheme(p, g, chunk)
    at = {}
    for i in range(1, 21):
        if i in (10, 20):
            at[i] = distance(traj, chunk - 1.0)
        if i < 20:
            end, _ = state_at(traj, g, chunk - 1.0)
            traj = simulate_from(p, g, end, chunk)
    elapsed = 10 * (chunk - 1.0)           # model time between the two measurements
    lead = max(abs(v) for v in o.multipliers.nontrivial)
    predicted = math.log(lead) / o.period
    assert at[20] < 0.02
    assert abs(math.log(at[20] / at[10]) / elapsed / predicted - 1) < 0.1
