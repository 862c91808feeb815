"""The pieces of the n-slip seed (core.orbit_seed): slip onsets, the tiled cycle, and a
run's carried state on the orbit's grid, on trajectories written down by hand."""

from __future__ import annotations

import math

import numpy as np
import pytest

from core.history import CarriedState
from core.orbit import Grid, OrbitError
from core.orbit_seed import slip_onsets, slips_per_return, state_from_carried, tiled_cycle
from core.params import Params


def written(g: Grid, t_end: float, m_y) -> np.ndarray:
    """A trajectory (orbit layout) with m_y(t) given, m_x its integral, s_x = t, s_y = 2t,
    u = 3t."""
    t = (np.arange(g.n_delay + math.ceil(t_end / g.dt) + 1) - g.n_delay) * g.dt
    y = m_y(t)
    x = np.concatenate(([0.0], np.cumsum(0.5 * (y[1:] + y[:-1]) * g.dt)))
    return np.vstack((x, y, t, 2 * t, 3 * t))


G = Grid.of(Params(tau=10.0), 0.01)


def test_onsets_and_slips_per_return():
    """Three unequal pulses every 10.5 (gaps 2, 3.5, 5): one onset each, three a return."""
    def pulses(t):
        ph = np.mod(t, 10.5)
        return sum(np.exp(-((ph - c) / 0.2) ** 2) for c in (1.0, 3.0, 6.5))
    traj = written(G, 200.0, pulses)
    on = slip_onsets(traj, G, 50.0)
    assert len(on) >= 13                     # 50 time units, 3 a return of 10.5
    assert np.allclose(sorted(np.diff(on)[:3]), [2.0, 3.5, 5.0], atol=1e-9)
    assert slips_per_return(traj, G, 10.5) == 3


def test_the_tile_repeats_the_cycle_with_m_x_drifting():
    """A cycle [start, end] stretched to P: the history is P-periodic in m_y, and m_x
    falls by the cycle's drift each P back (continuous across the tiles)."""
    traj = written(G, 100.0, lambda t: 1.0 + np.sin(2 * np.pi * t / 4.0))
    start, end, period = 50.0, 54.0, 2.5  # one 4-unit cycle stretched to 2.5
    z = tiled_cycle(traj, G, start, end, period)
    n = G.n_delay
    xi, eta = z[4:4 + n], z[4 + n:]
    j = round(period / G.dt)           # 250 steps: one tile back
    assert np.allclose(eta[j:], eta[:-j], atol=1e-6)
    drift = 4.0                              # the integral of m_y over one 4-unit cycle
    assert np.allclose(xi[j:] - xi[:-j], -drift, atol=1e-6)
    assert np.max(np.abs(np.diff(xi))) < 0.05  # no jump at the joins
    assert z[0] == pytest.approx(1.0 + np.sin(2 * np.pi * 50.0 / 4.0), abs=1e-6)


def test_a_carried_state_on_the_orbit_grid():
    """A run's state (Euler-like step 1e-3): m_x over the delay, now; m_y from its slope."""
    tau, dt = 10.0, 1e-3
    t = -tau + dt * np.arange(round(tau / dt))
    c = CarriedState(tau, dt, np.array([np.sin(0.0), np.cos(0.0), 0.1, 0.2, 0.3]), np.sin(t))
    z = state_from_carried(c, G)
    back = -G.dt * np.arange(1, G.n_delay + 1)
    n = G.n_delay
    assert np.allclose(z[:4], [1.0, 0.1, 0.2, 0.3])
    assert np.allclose(z[4:4 + n], np.sin(back), atol=1e-6)
    assert np.allclose(z[4 + n:], np.cos(back), atol=1e-5)
    with pytest.raises(OrbitError, match="tau = 5"):
        state_from_carried(CarriedState(5.0, dt, c.now, c.m_x[:5000]), G)
