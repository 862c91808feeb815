"""Period doublings, tori and branch points are reported only where a multiplier really
crosses the unit circle (core.multiplier_crossing).

On the upper Hopf branches at tau = 10 (d = 1e-4) the N-slip orbits keep 2 (N - 1)
multipliers within ~1e-5 of the N-th roots of unity, in nearly defective clusters whose
moduli move by more than that under dt -> dt/2: the continuation used to mark a period
doubling or a torus wherever the last digits flipped (N = 2: at k = 9.03, 9.53, 10.01;
N = 3: tori at 16.3, 17.95, 18.5), and a period doubling at k = 3.95 on N = 2 and a torus
at 4.49 on N = 3 where the fold's own multiplier crossed +1. These are now undetermined,
with the figures, or not marked at all."""

from __future__ import annotations

import functools
import itertools

import numpy as np
import pytest

from core.branch_start import MIN_STEP, BranchSpec, past_end, start
from core.branch_switch import half_shift, period_doubled
from core.continuation import bifurcations, walk
from core.orbit_seed import simulate_from
from core.params import Params
from core.shooting import correct

pytestmark = pytest.mark.computation  # only computes: beside the slow tiers (tests/xdist_plan.py)


@functools.cache
def _branch(n: int):
    spec = BranchSpec(Params(tau=10.0), "k", 0.01, True, 25.0, hopf_branch=n)
    branch, _ = start(spec)
    for _ in walk(branch, lambda q: past_end(spec, branch.points[0].value, q), spec.max_points,
                  MIN_STEP):
        pass
    return branch


#: The one clear crossing on each branch: the N = 2 pair near -1 enters the circle as a
#: complex pair (|mu| - 1 = +6.8e-4 at k = 4.86, -9.1e-5 at 5.36, uncertain by 5e-7 and
#: 6e-8), the N = 3 pairs near the cube roots of unity (+2.3e-5 at 9.78, -1.1e-4 at 10.78,
#: uncertain by 2e-7 and 2e-6): tori next to the strong resonances 1:2 and 1:3.
CLEAR_CROSSING = {2: (5.2567, "1:2"), 3: (9.8623, "1:3")}


@pytest.mark.parametrize("n", [2, 3])
def test_the_upper_hopf_branches_mark_no_crossing_within_the_round_off(n):
    found = bifurcations(_branch(n))
    kinds = [b.type for b in found]
    assert kinds.count("fold") == 1
    crossings = [b for b in found if b.type in ("period-doubling", "torus", "branch-point")]
    (torus,) = crossings
    value, resonance = CLEAR_CROSSING[n]
    assert torus.type == "torus" and abs(torus.value - value) < 1e-3
    assert abs(abs(torus.multiplier) - 1) < 1e-6 and f"{resonance} resonance" in torus.reason
    # past it the near-neutral multipliers stay within ~1e-5 of the circle: every flip
    # there is undetermined
    undetermined = [b for b in found if b.type == "undetermined"]
    assert len(undetermined) >= 3
    assert all(b.value > value and "dt -> dt/2" in b.reason for b in undetermined)


def _slip_asymmetry(k: float, t_end: float) -> tuple[np.ndarray, np.ndarray, float]:
    """A direct RK4 run at k from the corrected 2-slip orbit plus a kick of 1e-4: the
    times and the differences of consecutive slip intervals (odd minus even), and the
    orbit's period."""
    branch = _branch(2)
    n, g = branch.g0.size, branch.g0
    upper = [y for (y, _), pt in zip(branch.states, branch.points, strict=True)
             if pt.tangent_p > 0 and pt.amplitude > 1.3]
    j = max(i for i in range(len(upper) - 1) if upper[i][-1] <= k)
    s = (k - upper[j][-1]) / (upper[j + 1][-1] - upper[j][-1])
    y = upper[j] + s * (upper[j + 1] - upper[j])
    pm = branch.map_at(k)
    sol = correct(pm, y[:n], float(y[n]), y[:n], pm.shoot(y[:n], float(y[n])).d_dT)
    kick = np.random.default_rng(1).standard_normal(n) / np.sqrt(g.weights * n)
    my = simulate_from(pm.p, g, sol.z + 1e-4 * kick, t_end)[1, g.n_delay:]
    mid = 0.5 * (my.max() + my.min())
    up = np.nonzero((my[:-1] < mid) & (my[1:] >= mid))[0]
    onsets = (up + (mid - my[up]) / (my[up + 1] - my[up])) * g.dt
    d = np.diff(onsets)
    m = d.size // 2 * 2
    return onsets[1:m:2], d[1:m:2] - d[0:m:2], sol.period


def _envelope(t: np.ndarray, a: np.ndarray, block: int = 200) -> tuple[np.ndarray, np.ndarray]:
    nb = a.size // block
    return (t[:nb * block].reshape(nb, block).mean(axis=1),
            np.abs(a[:nb * block]).reshape(nb, block).max(axis=1))


def test_a_simulation_grows_away_from_the_2_slip_orbit_below_its_torus_and_not_above():
    """Below k = 5.2567 the slips' asymmetry (the mode of the pair near -1) grows at the
    rate the multipliers give (k = 5.0: |mu| - 1 = +3.66e-4 a period; measured 3.83e-4
    over t = 2e3 to 6e4, the pair's slow turn, 4.8e-4 rad a period, modulating it);
    above it, it decays (k = 5.5, |mu| - 1 = -1.87e-4: measured, the largest |asymmetry|
    after t = 4e4 is 0.54 of that over 5e3 to 1.5e4, reading slip times has a 5e-5
    floor)."""
    t, a, period = _slip_asymmetry(5.0, 60_000.0)
    tb, ab = _envelope(t, a)
    rate = np.polyfit(tb[tb > 2000], np.log(ab[tb > 2000]), 1)[0] * period
    assert 2.5e-4 < rate < 4.8e-4
    t, a, _ = _slip_asymmetry(5.5, 50_000.0)
    early, late = np.abs(a[(t > 5e3) & (t < 1.5e4)]).max(), np.abs(a[t > 4e4]).max()
    assert late < 0.7 * early


# --- a real period doubling, and the branch born there -----------------------------------
#
# b at tau = 2, k = 12 (a = 3.2, c = 4.8, d = 1e-4, v = 0.1), from the Hopf point at
# b = 3.675: the orbit grows (amplitude 8.8 at b = 22.3, past eq. 12's b^2 < 4ac) and a
# real multiplier runs from +0.07 at b = 22.300 to -1.02 at 22.3255: a period doubling at
# b = 22.32519 (period 4.01147), undone at 22.33167, and another at 22.3460. At dt = 0.01
# the orbit is not resolved there (the flow multiplier 4e-3 off 1, the crossing
# multiplier moving by 0.19 under dt -> dt/2: undetermined); at dt = 0.0025 it is (1e-6,
# and 6e-4 and 1.9e-3 against |mu| - 1 = -0.39 and +0.02 on the two sides).

PD_DT = 0.0025


@pytest.fixture(scope="module")
def b_branch():
    spec = BranchSpec(Params(tau=2.0, k=12.0), "b", PD_DT, True, 22.335, max_points=120)
    branch, _ = start(spec)
    for _ in walk(branch, lambda q: past_end(spec, branch.points[0].value, q), spec.max_points,
                  MIN_STEP):
        pass
    return branch, bifurcations(branch)


def test_a_period_doubling_is_found_and_located(b_branch):
    _, found = b_branch
    pds = [b for b in found if b.type == "period-doubling"]
    assert [b.type for b in found if b.type not in ("period-doubling",)] == []
    assert len(pds) == 2  # there and back: a bubble of period-doubled orbits
    first, back = pds
    assert abs(first.value - 22.32519) < 2e-5 and abs(first.period - 4.01147) < 1e-4
    assert abs(first.multiplier + 1) < 1e-6
    assert abs(back.value - 22.33167) < 5e-5
    assert "located within" in first.reason


def _maxima(p: Params, z, g, t_end: float) -> np.ndarray:
    """The maxima of m_y (upper half of its range) over the last 60 time units of a direct
    RK4 simulation from the reduced state z."""
    traj = simulate_from(p, g, z, t_end)
    my = traj[1, g.n_delay:]
    late = my[-int(60 / g.dt):]
    peak = (late[1:-1] > late[:-2]) & (late[1:-1] >= late[2:])
    peak &= late[1:-1] > late.min() + 0.5 * np.ptp(late)
    return late[1:-1][peak]


def test_a_simulation_shows_the_simple_orbit_before_and_the_doubled_one_after(b_branch):
    """Direct RK4 runs from the branch's orbit near b = 22.3255, at the same dt: 0.0012
    before the period doubling the maxima of m_y are equal (to the 1e-5 of sampling them on
    the grid), 0.0028 after it they alternate by 4.9e-4 (the period-doubled orbit, stable:
    the simple one's multiplier is -1.23 there)."""
    branch, found = b_branch
    n = branch.g0.size
    i = min(range(len(branch.points)), key=lambda j: abs(branch.points[j].value - 22.3255))
    z = branch.states[i][0][:n]
    pd = next(b for b in found if b.type == "period-doubling").value
    before = _maxima(Params(tau=2.0, k=12.0, b=pd - 0.0012), z, branch.g0, 1500.0)
    after = _maxima(Params(tau=2.0, k=12.0, b=pd + 0.0028), z, branch.g0, 1500.0)
    assert np.ptp(before) < 5e-5
    assert np.all(np.abs(np.diff(after)) > 3e-4)          # alternating heights
    assert np.ptp(after[::2]) < 5e-5 and np.ptp(after[1::2]) < 5e-5


def test_the_period_doubled_branch_leaves_the_doubled_orbit_as_a_square_root(b_branch):
    """From the period doubling: orbits of period ~2T whose distance d to their own
    half-period shift (0 on the old orbit traversed twice) grows as sqrt(b - b_0) (a
    log-log slope of 0.5 near the point; measured 0.47 over b - b_0 < 1.2e-3). b_0 is
    where the 2T branch leaves, its first orbit (eps = 0.01 along the flip vector):
    22.32517, 1.9e-5 below where the T map's multiplier is -1, as the map over 2T is not
    exactly the T map twice (each reads the state at its period by interpolation), well
    within the period doubling's own dt error (6e-4 between dt = 0.005 and 0.0025)."""
    branch, found = b_branch
    pd = next(b for b in found if b.type == "period-doubling")
    new = period_doubled(branch, pd, step=0.02, max_step=0.05)
    n = branch.g0.size
    rows = []
    for point in walk(new, lambda q: False, 7, MIN_STEP):
        y, _ = new.states[-1]
        rows.append((point.value, point.period,
                     half_shift(new.map_at(point.value), y[:n], point.period)))
    b0 = rows[0][0]
    assert abs(b0 - pd.value) < 5e-5
    assert all(abs(period / (2 * pd.period) - 1) < 2e-3 for _, period, _ in rows)
    assert all(d > 1e-2 for _, _, d in rows)                # not the old orbit twice
    grown = [(b - b0, d) for b, _, d in rows[1:]]
    assert all(db > 0 for db, _ in grown)
    slope = np.polyfit(np.log([db for db, _ in grown]), np.log([d for _, d in grown]), 1)[0]
    assert 0.42 < slope < 0.55
    assert new.points[1].stable  # supercritical: the simulation's doubled orbit


def test_the_period_doubling_continued_in_k_keeps_a_multiplier_at_minus_one(b_branch):
    """The period doubling as a curve in (b, k) (core.flip_continuation), from the one this
    branch locates by regula falsi on the multiplier: its first point, corrected by Newton
    on the bordered test function instead, is the same period doubling, and at every point
    the Floquet solver (ARPACK, apart from the bordered system) finds a multiplier at -1."""
    from core.flip_continuation import flip_curve_at
    from core.fold_continuation import walk as walk_curve

    branch, found = b_branch
    pd = next(b for b in found if b.type == "period-doubling")
    curve = flip_curve_at(branch, pd, "k", max_step=0.05)
    points = list(walk_curve(curve, 12.1, 20))
    assert curve.end == "reached k = 12.1" and len(points) >= 3
    assert abs(points[0].first - pd.value) < 1e-6 and points[0].second == 12.0
    assert points[-1].second == 12.1
    bs = [p.first for p in points]
    assert all(a < b for a, b in itertools.pairwise(bs))  # b rises with k along it
    for p in points:
        assert np.min(np.abs(p.multipliers.nontrivial + 1.0)) < 1e-6, (p.first, p.second)
        assert abs(p.period - pd.period) < 1e-2


def test_continue_switch_pd_follows_the_doubled_branch(b_branch):
    """What `continue --switch-pd` adds to its JSON (slopetui.cli.continuation._doubled), on
    this branch: the period-2T orbits from its first period doubling, each with its
    half-period shift, which grows from zero as the orbits leave the doubled old one."""
    import argparse

    from slopetui.cli.continuation import _doubled

    branch, found = b_branch
    spec = BranchSpec(Params(tau=2.0, k=12.0), "b", PD_DT, True, 22.335, max_points=12)
    out = _doubled(argparse.Namespace(param="b"), spec, branch, found)
    pd = next(b for b in found if b.type == "period-doubling")
    assert out["at"]["value"] == pd.value and "switched at the period doubling" in out["note"]
    points = out["branch"]
    assert 3 <= len(points) <= 12
    assert abs(points[0]["period"] - 2 * pd.period) < 1e-2
    shifts = [p["half_shift"] for p in points]
    assert shifts[0] < 0.1 < max(shifts)
