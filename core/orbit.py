"""Periodic orbits of the discretised delay equation: shooting, Newton-Krylov, Floquet.

The state (core.period_map) is the five variables and (m_x, m_y) over one delay. m_x
enters eqs. 6a-6e only as m_x(t - tau) - m_x(t): a common shift of m_x is neutral (its
multiplier is exactly 1). The unknowns drop it, as lambda_max does: the reduced state is

    z = [m_y, s_x, s_y, u, xi_1..xi_N, eta_1..eta_N],
    xi_j = m_x(-j dt) - m_x(0),  eta_j = m_y(-j dt),       N = tau / dt,

2N + 4 numbers (2004 at tau = 10, dt = 0.01). The period map P(z, T) integrates RK4 from
z for T and reads the state at T from the trajectory by cubic Lagrange interpolation in
time (4th order, as RK4), so T is a continuous unknown and dP/dT is the interpolant's
time derivative. A periodic orbit solves P(z, T) = z with the phase condition
<zdot_ref, z - z_ref> = 0; Newton's method solves it, each step by GMRES on the
matrix-free Jacobian (one tangent integration over a period per product). The Floquet
multipliers are the eigenvalues of dP/dz, the leading ones by Arnoldi (ARPACK).

Inner products weight the history by 1/N: the current state and the history over one
delay count alike, whatever dt.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from core.model import coefficients
from core.params import Params
from core.period_map import flow

#: Newton stops when the residual |P(z, T) - z| (weighted norm) falls below this. RK4 at
#: dt = 0.01 is accurate to ~1e-9 over a period (numerics notes); a tighter tolerance
#: resolves the discrete map's own orbit, which is what the multipliers describe.
NEWTON_TOL = 1e-10
#: Newton steps before giving up (quadratic convergence takes 3 to 6 from a seed
#: simulated to within 1e-4 of the orbit).
NEWTON_MAX = 25
#: GMRES's relative tolerance for one Newton step (inexact Newton: tightened as the
#: residual falls, never looser than this).
GMRES_RTOL = 1e-6
#: The most RK4 steps one shot integrates. A Newton step far off an orbit can ask for any
#: period: a continuation in c at tau = 2, k = 12 asked for ~1e9 near c = -42.6 and died of
#: a MemoryError allocating its trajectory (40 bytes a step, and as much again for each
#: product with dP/dz). 1e6 steps is a period of 1e4 at dt = 0.01; the longest periods
#: continued are ~60 (small k, tau = 20): 6000 steps.
MAX_SHOT_STEPS = 1_000_000


class OrbitError(ValueError):
    """No periodic orbit could be found or continued; the message says why."""


@dataclass(frozen=True)
class Grid:
    """The delay grid: tau = n_delay * dt exactly."""

    dt: float
    n_delay: int

    @staticmethod
    def of(p: Params, dt: float) -> Grid:
        if p.tau <= 0.0:
            raise OrbitError("tau must be > 0: periodic orbits of this model need a delay")
        n = max(1, math.ceil(p.tau / dt - 1e-9))
        return Grid(p.tau / n, n)

    @property
    def size(self) -> int:
        return 2 * self.n_delay + 4

    @property
    def weights(self) -> np.ndarray:
        w = np.full(self.size, 1.0 / self.n_delay)
        w[:4] = 1.0
        return w


def lagrange(theta: float) -> tuple[np.ndarray, np.ndarray]:
    """Cubic Lagrange weights on the nodes -1, 0, 1, 2 at theta in [0, 1), and their
    derivatives in theta."""
    t = theta
    w = np.array([-t * (t - 1) * (t - 2) / 6, (t + 1) * (t - 1) * (t - 2) / 2,
                  -(t + 1) * t * (t - 2) / 2, (t + 1) * t * (t - 1) / 6])
    dw = np.array([-(3 * t * t - 6 * t + 2) / 6, (3 * t * t - 4 * t - 1) / 2,
                   -(3 * t * t - 2 * t - 2) / 2, (3 * t * t - 1) / 6])
    return w, dw


def to_columns(z: np.ndarray, g: Grid, n_steps: int) -> np.ndarray:
    """A trajectory array (5, N + n_steps + 1) whose first N + 1 columns hold z (m_x = 0
    at step 0)."""
    n = g.n_delay
    traj = np.zeros((5, n + n_steps + 1))
    traj[1:, n] = z[:4]
    traj[0, n - 1::-1] = z[4:4 + n]          # xi_j at column n - j
    traj[1, n - 1::-1] = z[4 + n:]
    return traj


def reduce_at(traj: np.ndarray, g: Grid, col: int, w: np.ndarray) -> np.ndarray:
    """The reduced state at the time sum_i w_i t_(col - 1 + i), from a trajectory."""
    n = g.n_delay
    now = traj[:, col - 1:col + 3] @ w
    # m_x and m_y at the N earlier times, each from its own four columns
    idx = col - 1 - np.arange(1, n + 1)[:, None] + np.arange(4)[None, :]
    xs = traj[0, idx] @ w
    ys = traj[1, idx] @ w
    return np.concatenate((now[1:], xs - now[0], ys))


def integrate(coef: np.ndarray, g: Grid, traj: np.ndarray, what: str, then: str = "") -> np.ndarray:
    """Fill ``traj`` with RK4 steps from its first N + 1 columns (core.period_map.flow) and
    return it; OrbitError naming ``what`` (and ``then``, what that means) when it leaves
    the finite range (|m_y| or |s_y| > 1e6)."""
    filled = flow(coef, g.dt, g.n_delay, traj, traj, False)
    if filled < traj.shape[1]:
        raise OrbitError(f"{what} left the finite range (|m_y| or |s_y| > 1e6) at t = "
                         f"{(filled - g.n_delay) * g.dt:.4g}" + (f": {then}" if then else ""))
    return traj


@dataclass
class Shot:
    """One evaluation of the period map: P(z, T), dP/dT, and what the tangent needs."""

    value: np.ndarray
    d_dT: np.ndarray
    traj: np.ndarray
    col: int
    w: np.ndarray


class PeriodMap:
    """P(z, T) for one parameter point and grid, with its derivatives."""

    def __init__(self, p: Params, g: Grid) -> None:
        self.p, self.g = p, g
        self.coef = coefficients(p)

    def steps(self, T: float) -> tuple[int, float]:
        """Whole steps of dt in T and the fraction left; OrbitError for a period no shot
        integrates (not finite, or more than MAX_SHOT_STEPS steps)."""
        if not math.isfinite(T) or T / self.g.dt > MAX_SHOT_STEPS:
            raise OrbitError(f"a period of {T:.4g} is beyond one shot ({MAX_SHOT_STEPS:,} steps "
                             f"of dt = {self.g.dt:g}): Newton has left the orbit")
        m = math.floor(T / self.g.dt)
        return max(m, 1), T / self.g.dt - max(m, 1)

    def shoot(self, z: np.ndarray, T: float) -> Shot:
        m, theta = self.steps(T)
        traj = integrate(self.coef, self.g, to_columns(z, self.g, m + 2),
                         "the trajectory of one period")
        w, dw = lagrange(theta)
        col = self.g.n_delay + m
        value = reduce_at(traj, self.g, col, w)
        d_dT = reduce_at(traj, self.g, col, dw) / self.g.dt
        return Shot(value, d_dT, traj, col, w)

    def tangent(self, shot: Shot, v: np.ndarray) -> np.ndarray:
        """dP/dz v along the trajectory of ``shot`` (the exact derivative of the map)."""
        e = to_columns(v, self.g, shot.traj.shape[1] - self.g.n_delay - 1)
        traj = shot.traj.copy()  # flow rewrites the trajectory it integrates
        flow(self.coef, self.g.dt, self.g.n_delay, traj, e, True)
        return reduce_at(e, self.g, shot.col, shot.w)

    def translation_multiplier(self, shot: Shot) -> float:
        """The multiplier of a common shift of m_x, in full coordinates: exactly 1 when the
        model and the scheme keep the symmetry (the built-in check the multipliers carry)."""
        e = np.zeros_like(shot.traj)
        e[0, :self.g.n_delay + 1] = 1.0
        traj = shot.traj.copy()
        flow(self.coef, self.g.dt, self.g.n_delay, traj, e, True)
        now = e[:, shot.col - 1:shot.col + 3] @ shot.w
        others = float(np.abs(now[1:]).max())
        return float(now[0]) if others == 0.0 else math.nan
