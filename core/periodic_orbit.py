"""One periodic orbit of eqs. 6a-6e: found from a simulation, corrected by Newton-Krylov
shooting (core.shooting), with its Floquet multipliers (core.floquet).

    orbit = find_orbit(Params(k=10, tau=10))
    orbit.period, orbit.amplitude, orbit.multipliers.stable

The orbit belongs to RK4 at dt (default 0.01, 4th order: the period is accurate to
~1e-9 relative against finer dt), the scheme slopetui's RK4 runs use.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from core.classify import find_peaks
from core.floquet import Multipliers, multipliers
from core.orbit import Grid, OrbitError, PeriodMap
from core.orbit_seed import (
    SLIP_PERIOD_TOL,
    find_return,
    n_slip_seed,
    simulate,
    simulate_from,
    slips_per_return,
    state_at,
)
from core.params import Params
from core.shooting import Solution, correct

#: The default step of orbit computations (RK4): as RK4 runs (core.solve.DEFAULT_DT).
ORBIT_DT = 0.01
#: The seed simulation's length in delays and basic periods: long enough that a stable
#: orbit has been approached (transients near the Hopf curve decay at ~1e-4 per unit
#: time, so the seed may still be off by a few percent: Newton does the rest).
SEED_T_END = 3000.0
#: The part of the seed run in which returns are looked for.
SEED_SPAN = 600.0

__all__ = ["ORBIT_DT", "Orbit", "OrbitError", "find_orbit", "orbit_from"]


@dataclass(frozen=True)
class Orbit:
    """A periodic orbit: its parameters and grid, reduced state on the section, period,
    multipliers, and Newton's account (steps, residual, Krylov products)."""

    params: Params
    grid: Grid
    z: np.ndarray
    period: float
    multipliers: Multipliers
    m_y: np.ndarray          # m_y over one period, every step (for amplitude and maxima)
    newton_steps: int
    residual: float
    products: int
    slips: int = 1           # slips a period the seed aimed at (core.orbit_seed.n_slip_seed)

    @property
    def amplitude(self) -> float:
        """Peak-to-peak m_y over one period."""
        return float(np.ptp(self.m_y))

    @property
    def maxima_per_period(self) -> int:
        """Local maxima of m_y in one period (a period-1 orbit may have several)."""
        return maxima_in(self.m_y)

    @property
    def stable(self) -> bool:
        return self.multipliers.stable


def maxima_in(m_y: np.ndarray) -> int:
    """Local maxima of ``m_y`` over one period (sampled every step, first and last sample
    the same point)."""
    y = np.concatenate((m_y, m_y[1:3]))  # wrap around the section
    t = np.arange(y.size, dtype=float)
    peak_t, _ = find_peaks(t, y)
    return int(np.sum((peak_t >= 1) & (peak_t < m_y.size)))


def orbit_from(p: Params, g: Grid, sol: Solution, count: int = 10, slips: int = 1) -> Orbit:
    """An Orbit from a corrected solution: its multipliers and one period of m_y."""
    pm = PeriodMap(p, g)
    mult = multipliers(pm, sol.shot, count)
    n = g.n_delay
    m_y = sol.shot.traj[1, n:sol.shot.col + 1]
    return Orbit(p, g, sol.z, sol.period, mult, m_y, sol.steps, sol.residual, sol.products,
                 slips)


def find_orbit(p: Params, dt: float = ORBIT_DT, t_seed: float = SEED_T_END,
               count: int = 10, slips: int | None = None,
               start: np.ndarray | None = None) -> Orbit:
    """The periodic orbit a simulation from eq. 19 (offset p.delta), or from the reduced
    state ``start`` (a run's final state: core.orbit_seed.state_from_carried), settles on.

    The simulation's last return T holds m slips. With one, Newton starts from the
    return. With m > 1 it does too, and when that fails (the slips are a slow transient
    towards equal spacing, not an orbit of period T) Newton starts from the equally spaced
    m-slip seed (core.orbit_seed.n_slip_seed), period T / m. ``slips`` = n asks for the
    equally spaced n-slip orbit of period T / n whatever m is.

    Raises OrbitError when the run comes to rest, diverges, or does not return (a torus
    or chaos), or when Newton does not converge, or converges to an orbit whose period is
    not T / n: the message says which.
    """
    g = Grid.of(p, dt)
    length = max(t_seed, 4 * p.tau + SEED_SPAN)
    traj = simulate(p, g, length) if start is None else simulate_from(p, g, start, length)
    t0, period = find_return(traj, g, min(SEED_SPAN, t_seed / 2))
    pm = PeriodMap(p, g)
    m = slips_per_return(traj, g, period)
    if slips is None:
        z0, zdot = state_at(traj, g, t0)
        try:
            return orbit_from(p, g, correct(pm, z0, period, z0, zdot), count)
        except OrbitError:
            if m == 1:
                raise
        slips = m
    z0, zdot, target = n_slip_seed(p, g, traj, period, slips)
    try:
        sol = correct(pm, z0, target, z0, zdot)
    except OrbitError as exc:
        raise OrbitError(f"from the equally spaced {slips}-slip seed (period T / {slips} = "
                         f"{target:.6g}, T = {period:.6g} the simulation's return): {exc}") from None
    if abs(sol.period - target) > SLIP_PERIOD_TOL * target:
        raise OrbitError(f"Newton from the equally spaced {slips}-slip seed converged to an "
                         f"orbit of period {sol.period:.6g}, not T / {slips} = {target:.6g} "
                         f"(T = {period:.6g}, the simulation's return): no {slips}-slip orbit "
                         "near the seed")
    # the 2 (n - 1) near-circle multipliers, the flow's, and the next few
    return orbit_from(p, g, sol, max(count, 2 * slips + 4), slips)
