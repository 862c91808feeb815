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
