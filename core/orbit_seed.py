"""A first guess of a periodic orbit: simulate, then find where the state returns.

The run starts from eq. 19 (m_x = delta before t = 0, every variable delta at t = 0) and
is integrated by core.period_map's RK4, so the seed lies on the same discrete map that
Newton then corrects. Upward crossings of m_y through its mean over the last part of the
run are Poincare-section points; the return time is the shortest span after which the
reduced state (every variable and the history over one delay) comes back to within
RETURN_TOL of its amplitude.
"""

from __future__ import annotations

import math

import numpy as np

from core.history import CarriedState
from core.model import coefficients
from core.orbit import Grid, OrbitError, integrate, lagrange, reduce_at, to_columns
from core.params import Params

#: The state returns when its weighted distance from the last section point is below
#: this fraction of the orbit's amplitude (peak-to-peak m_y). Newton converges from much
#: farther (measured: from a seed 1e-2 off at k = 10, tau = 10 in 5 steps), so the seed
#: need not be settled; the tolerance only has to reject a wrong return.
RETURN_TOL = 5e-2
#: The seed is decaying towards rest when its amplitude falls by more than this fraction
#: between the first and last thirds of the span looked at (a transient near the steady
#: state: at k = 4, tau = 10 from delta = 0.1 it shrinks by 1e-3 a period, and Newton then
#: stalls on the steady state, which is a "periodic orbit" of any period).
DECAY_TOL = 1e-3
#: Section points compared (the longest return considered, in crossings).
MAX_CROSSINGS = 40


def simulate(p: Params, g: Grid, t_end: float) -> np.ndarray:
    """The trajectory from eq. 19 to t_end (rows m_x, m_y, s_x, s_y, u; column N is t = 0)."""
    n_steps = math.ceil(t_end / g.dt)
    traj = np.zeros((5, g.n_delay + n_steps + 1))
    traj[0, :] = p.delta
    traj[:, g.n_delay] = p.delta  # (19)
    return integrate(coefficients(p), g, traj, "the seed simulation",
                     "no bounded orbit to start from")


def state_at(traj: np.ndarray, g: Grid, t: float) -> tuple[np.ndarray, np.ndarray]:
    """The reduced state at time t and its time derivative (t on the trajectory's grid)."""
    s = t / g.dt
    m = math.floor(s)
    w, dw = lagrange(s - m)
    col = g.n_delay + m
    return reduce_at(traj, g, col, w), reduce_at(traj, g, col, dw) / g.dt


def find_return(traj: np.ndarray, g: Grid, span: float) -> tuple[float, float]:
    """(time of a section point, return time) in the last ``span`` of the run."""
    n0 = traj.shape[1] - int(span / g.dt) - 1
    y = traj[1, n0:]
    level = float(y.mean())
    amp = float(np.ptp(y))
    third = len(y) // 3
    early, late = float(np.ptp(y[:third])), float(np.ptp(y[-third:]))
    if amp < 1e-9 or late < (1 - DECAY_TOL) * early:
        raise OrbitError("the simulation came to rest or is decaying towards it (peak-to-peak "
                         f"m_y {early:.2g} then {late:.2g} over the last {span:g}): there is no "
                         "stable orbit to start from here (start from the Hopf point, another "
                         "run, or a larger delta)")
    up = np.nonzero((y[:-1] < level) & (y[1:] >= level))[0]
    if len(up) < 3:
        raise OrbitError("too few oscillations in the seed simulation to find a return")
    # crossing times by linear interpolation, in model time from t = 0
    frac = (level - y[up]) / (y[up + 1] - y[up])
    times = (n0 + up + frac - g.n_delay) * g.dt
    last = times[-1]
    z_last, _ = state_at(traj, g, last)
    w = g.weights
    for back in range(1, min(MAX_CROSSINGS, len(times) - 1) + 1):
        earlier = times[-1 - back]
        if earlier - g.n_delay * g.dt < 2.0:   # its history must lie in the run
            break
        z, _ = state_at(traj, g, earlier)
        d = z - z_last
        if math.sqrt(float(np.dot(d * w, d))) < RETURN_TOL * amp:
            return earlier, last - earlier
    raise OrbitError("the simulated state does not return within "
                     f"{MAX_CROSSINGS} oscillations: no periodic orbit near it (a torus or "
                     "chaos; core.classify tells which)")


def simulate_from(p: Params, g: Grid, z: np.ndarray, t_end: float) -> np.ndarray:
    """The trajectory from the reduced state z (an orbit's, for instance) to t_end: how a
    simulation checks what the multipliers predict (stay on the orbit, or leave it)."""
    return integrate(coefficients(p), g, to_columns(z, g, math.ceil(t_end / g.dt)),
                     "the simulation")


# --- the equally spaced n-slip orbit ---------------------------------------------------
#
# At large k a run from eq. 19 reaches n slips per basic period T_1, unequally spaced, and
# equalises them over ~1e6 time units: the equally spaced orbit (period T_1 / n) has
# 2 (n - 1) multipliers within 1e-4 of the circle (at k = 18, tau = 10: the cube roots of
# unity times 0.999991 and 0.999896 for n = 3), so the run's state is still far from it
# along those directions, and Newton from it (period T_1) does not converge. The seed is
# built instead: one slip cycle of the run (onset to onset), stretched in time to T / n,
# repeated back over the delay with m_x advancing by the cycle's own drift each time (so
# m_x is continuous); then SLIP_PRE_DELAYS delays integrated, the result tiled again
# (from its cycle closest to T / n) and integrated as long, before Newton (period T / n).
#
# Measured (RK4 dt 0.01, 3000 time units from eq. 19; fifteen cases: tau = 10 and 8,
# k 10-25, delta 1e-6 to 1 (single-slip, 2- and 3-slip runs), n 2 and 3; a script over
# core.shooting.correct, on a machine shared by five; CPU < 0.3 s each). Newton converged
# to the orbit of period T / n (within 3e-4) in:
#   tile, 5 delays, tile again, 5 delays (this)    15 of 15,  62-180 Krylov products
#   tile, 10 delays                                15 of 15,  96-252
#   tile, 5 delays                                 14 of 15,  91-161
#   tile, 5 delays, tile again (no integration)    14 of 15,  90-519
#   tile alone (no pre-integration)                 9 of 12 (a short cycle stretched
#                                                  to a long period fails)
#   the longest cycle truncated to T / n (slip, then the stick phase cut), not
#   stretched, with or without 5 delays             9 of 12 (from a single-slip run it
#                                                  leaves the finite range)
# Newton from the run's own state (period T, the unequal slips) failed in the cases tried
# (k = 18, tau = 10, delta 1e-6 and 0.1: 25 steps, residual 7e-2).

#: Delays integrated from each tile before Newton (the table above).
SLIP_PRE_DELAYS = 5.0
#: Newton from the n-slip seed must land on an orbit of period T / n within this
#: fraction: the converged periods measured were within 3e-4 of T / n; a 4-slip seed at
#: k = 18, tau = 10 (no such orbit there) converged to an unstable one-slip orbit of
#: period 1.7346, 33 % off T / 4 = 2.596.
SLIP_PERIOD_TOL = 0.05


def slip_onsets(traj: np.ndarray, g: Grid, span: float) -> np.ndarray:
    """The times (from t = 0) at which m_y rises through the middle of its range over the
    last ``span`` of the run: one for each slip (a slip is m_y's large excursion; the
    stick phase's small wiggles stay below the middle)."""
    n0 = max(g.n_delay, traj.shape[1] - int(span / g.dt) - 1)
    y = traj[1, n0:]
    level = 0.5 * (float(y.min()) + float(y.max()))
    up = np.nonzero((y[:-1] < level) & (y[1:] >= level))[0]
    frac = (level - y[up]) / (y[up + 1] - y[up])
    return (n0 + up + frac - g.n_delay) * g.dt


def slips_per_return(traj: np.ndarray, g: Grid, period: float) -> int:
    """The slips in the run's last return (``period``, core.orbit_seed.find_return)."""
    onsets = slip_onsets(traj, g, 3.0 * period)
    end = (traj.shape[1] - 1 - g.n_delay) * g.dt
    return max(1, int(np.count_nonzero(onsets > end - period - 1e-9 - 0.5 * g.dt)))


def _at(traj: np.ndarray, g: Grid, t: np.ndarray) -> np.ndarray:
    """The five rows at the times t (linear interpolation: the seed's error, ~1e-5 of the
    curvature at dt = 0.01, is far inside Newton's reach)."""
    tt = (np.arange(traj.shape[1]) - g.n_delay) * g.dt
    return np.array([np.interp(t, tt, row) for row in traj])


def tiled_cycle(traj: np.ndarray, g: Grid, start: float, end: float, period: float) -> np.ndarray:
    """The reduced state that repeats the run's cycle [start, end], stretched to
    ``period``, back over the delay; the state now is the run's at ``start``."""
    s = g.dt * np.arange(1, g.n_delay + 1)          # time before now
    back = np.ceil(s / period - 1e-12)              # cycles back
    phase = back * period - s                       # in [0, period)
    hist = _at(traj, g, start + phase * (end - start) / period)
    now = _at(traj, g, np.array([start]))[:, 0]
    drift = float(_at(traj, g, np.array([end]))[0, 0]) - now[0]  # m_x's advance a cycle
    return np.concatenate((now[1:], hist[0] - now[0] - back * drift, hist[1]))


def _tile_nearest(traj: np.ndarray, g: Grid, span: float, target: float) -> np.ndarray:
    """tiled_cycle of the run's slip cycle (over its last ``span``) closest to ``target``."""
    onsets = slip_onsets(traj, g, span)
    if len(onsets) < 2:
        raise OrbitError("no slip cycle in the seed simulation to build the n-slip seed from")
    gaps = np.diff(onsets)
    i = int(np.argmin(np.abs(gaps - target)))
    return tiled_cycle(traj, g, float(onsets[i]), float(onsets[i + 1]), target)


def n_slip_seed(p: Params, g: Grid, traj: np.ndarray, period: float, n: int
                ) -> tuple[np.ndarray, np.ndarray, float]:
    """(state, its time derivative, period T / n) near the equally spaced n-slip orbit,
    from a run whose last return (``period`` T) is known: the run's slip cycle closest
    to T / n tiled (tiled_cycle), SLIP_PRE_DELAYS delays integrated, the integrated run's
    cycle closest to T / n tiled again and integrated as long (the second tile removes
    the unequal spacing the first integration kept: it is near-neutral)."""
    target = period / n
    z = _tile_nearest(traj, g, 2.5 * period, target)
    length = SLIP_PRE_DELAYS * p.tau + 2.0 * target
    z = _tile_nearest(simulate_from(p, g, z, length), g, length - p.tau, target)
    run = simulate_from(p, g, z, length)
    last = slip_onsets(run, g, 3.0 * target)
    # the last onset with two samples after it (state_at's cubic reads them)
    last = last[last < (run.shape[1] - 3 - g.n_delay) * g.dt]
    if len(last) == 0:
        raise OrbitError(f"the {n}-slip seed does not slip again (no slip onset in its last "
                         f"{3.0 * target:.4g}): no {n}-slip orbit near it")
    z0, zdot = state_at(run, g, float(last[-1]))
    return z0, zdot, target


def state_from_carried(c: CarriedState, g: Grid) -> np.ndarray:
    """The reduced state of a run's final state (core.history.CarriedState: the five
    variables at t_end and m_x over the delay before, on the run's own step) on the
    orbit's grid. The carried state holds no m_y history: it is m_x's slope (eq. 6a),
    by second-order differences on the run's grid (a seed only)."""
    if not math.isclose(c.tau, g.n_delay * g.dt, rel_tol=1e-9):
        raise OrbitError(f"the run's state spans tau = {c.tau:g}, the orbit's delay is "
                         f"{g.n_delay * g.dt:g}: a state seeds an orbit at its own tau")
    t = np.append(-c.tau + c.dt * np.arange(c.m_x.size), 0.0)
    x = np.append(c.m_x, c.now[0])
    y = np.gradient(x, t, edge_order=2)
    y[-1] = c.now[1]
    back = -g.dt * np.arange(1, g.n_delay + 1)
    return np.concatenate((c.now[1:], np.interp(back, t, x) - c.now[0], np.interp(back, t, y)))
