"""The kernels: Euler is the paper's algorithm exactly; RK4 converges at 4th order."""

from __future__ import annotations

import itertools
import os

import numba
import numpy as np
import pytest

from core import jit_cache
from core.params import Params
from core.recording import BLOWUP_BOUND
from core.solve import SolverSettings, simulate


def reference_euler(p: Params, dt: float, n_steps: int) -> np.ndarray:
    """A plain-Python transcription of eqs. 6a-6e with forward Euler and history delta."""
    n_delay = round(p.tau / dt)
    xs = [p.delta] * 5
    past = []  # m_x at every step
    for n in range(n_steps):
        x, y, sx, sy, u = xs
        if n_delay == 0:
            x_tau = x                      # no delay: the spring term vanishes
        else:
            x_tau = past[n - n_delay] if n >= n_delay else p.delta
        past.append(x)
        f1 = 3 * p.a * p.v**2 - 2 * p.b * p.v + p.c
        q = 3 * p.a * p.v - p.b
        g = f1 + 2 * q * y + 3 * p.a * (y * y + sy)
        dy = -f1 * y - q * y * y - p.a * y**3 - q * sy - 3 * p.a * y * sy + p.k * (x_tau - x)
        xs = [x + dt * y, y + dt * dy, sx + dt * 2 * u,
              sy + dt * (-2 * sy * g - 2 * p.k * u + 2 * p.d),
              u + dt * (-u * g - p.k * sx + sy)]
    return np.array(xs)


def final_state(p: Params, method: str, dt: float, t_end: float) -> np.ndarray:
    tr = simulate(p, SolverSettings(method=method, dt=dt, t_end=t_end, window=dt, lyap=False,
                                    trace_points=2))
    return tr.trace[:, -1]


@pytest.mark.parametrize("tau", [0.0, 0.05, 0.5])
def test_euler_kernel_is_the_papers_algorithm(tau):
    p = Params(k=12.0, tau=tau, d=1e-3)
    dt = 0.01
    got = final_state(p, "euler", dt, 3.0)
    want = reference_euler(p, dt, 300)
    assert np.allclose(got, want, rtol=1e-12, atol=1e-14)


@pytest.mark.parametrize("tau", [10.0, 0.5, 0.0])
def test_rk4_converges_at_fourth_order(tau):
    """Observed order log2(|y_h - y_{h/2}| / |y_{h/2} - y_{h/4}|) -> 4, across the kinks
    that the constant history puts at t = j tau (measured at tau = 10: 4.35, 4.24, 4.13),
    and without delay (tau = 0: the spring term vanishes)."""
    p = Params(k=10.0, tau=tau)
    states = [final_state(p, "rk4", dt, 50.0) for dt in (0.1, 0.05, 0.025, 0.0125, 0.00625)]
    diffs = [np.max(np.abs(a - b)) for a, b in itertools.pairwise(states)]
    orders = [np.log2(diffs[i] / diffs[i + 1]) for i in range(len(diffs) - 1)]
    assert all(3.8 < o < 4.5 for o in orders), orders
    assert abs(orders[-1] - 4.0) < 0.2, orders


def test_euler_converges_at_first_order():
    p = Params(k=10.0, tau=1.0)
    states = [final_state(p, "euler", dt, 20.0) for dt in (4e-3, 2e-3, 1e-3)]
    ratio = np.max(np.abs(states[0] - states[1])) / np.max(np.abs(states[1] - states[2]))
    assert 1.8 < ratio < 2.2


def test_initial_conditions_are_eq_19():
    tr = simulate(Params(delta=0.37), SolverSettings(t_end=10, window=1, lyap=False))
    assert np.all(tr.trace[:, 0] == 0.37)
    assert tr.trace_t[0] == 0.0


def test_window_and_trace_cover_the_end_without_the_whole_run():
    s = SolverSettings(t_end=2000, window=100, lyap=False)
    tr = simulate(Params(), s)
    assert tr.window_t[0] == pytest.approx(1900) and tr.window_t[-1] == pytest.approx(2000)
    assert tr.window.shape[1] <= 100 / 0.01 + 1          # sampled every 0.01, not every step
    assert tr.trace.shape[1] <= s.trace_points + 1
    assert np.all(np.isfinite(tr.window))


def test_blow_up_stops_the_run_and_reports_its_time():
    tr = simulate(Params(a=0.035, k=12.0, tau=5.0), SolverSettings(t_end=100, window=10))
    assert tr.blew_up and 0.0 < tr.t_blowup < 1.0
    assert tr.window.shape[1] == 0                       # never reached the window
    assert np.all(np.abs(tr.trace[1]) < BLOWUP_BOUND)    # samples stop before the bound


def test_kernel_cache_is_keyed_by_the_engine_source():
    """An edit to any core/*.py (e.g. model.py, inlined into the kernels) must not reuse
    kernels compiled from the old source."""
    if os.environ.get("NUMBA_CACHE_DIR"):
        assert os.environ["NUMBA_CACHE_DIR"] == numba.config.CACHE_DIR
    else:
        assert numba.config.CACHE_DIR.endswith(jit_cache.source_digest())
