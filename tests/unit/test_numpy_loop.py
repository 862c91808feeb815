"""The plain Python Euler loop of the peer benchmark integrates the same model as core.

benchmarks/bench_peers.py times benchmarks/numpy_euler.py as the stand-in for the paper's
MATLAB loop. The comparison only means something if the loop is the same discrete map as
core's Euler kernel: same grid, same constant history, same ring-buffer delay. It is
written independently (the paper's form of eqs. 6a-6e, a deque for the buffer), so the
two agree to round-off, not bit for bit.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from core.params import Params
from core.solve import SolverSettings, simulate

# benchmarks/ is a folder of scripts, not a package: import the loop by path
sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
from numpy_euler import euler_loop


@pytest.mark.parametrize(
    ("params", "dt", "t_end"),
    [
        # 400 steps over 4 delays: the 100-slot buffer wraps four times
        (Params(tau=1.0, k=10.0), 1e-2, 4.0),
        # the paper's dt: 2500 steps over 2.5 delays, at another point with a stiffer spring
        (Params(tau=1.0, k=40.0, delta=0.5), 1e-3, 2.5),
        # tau not a multiple of dt: both take dt' = tau / ceil(tau / dt)
        (Params(tau=0.95, k=10.0), 3e-2, 3.0),
    ],
)
def test_loop_matches_core_euler(params: Params, dt: float, t_end: float) -> None:
    stride = max(1, round(0.01 / dt))  # core samples its window every 0.01 time units
    t, states = euler_loop(params, dt, t_end, stride=stride)
    tr = simulate(params, SolverSettings(method="euler", dt=dt, t_end=t_end, window=t_end, lyap=False))
    assert not tr.blew_up
    assert states.shape == tr.window.shape
    np.testing.assert_allclose(t, tr.window_t, rtol=0.0, atol=1e-12)
    # per variable, relative to its scale: u and s_x pass through zero
    scale = np.abs(tr.window).max(axis=1, keepdims=True)
    err = np.abs(states - tr.window) / scale
    assert err.max() < 1e-12, err.max(axis=1)
    # and the run really moved: the delay fed back (m_y left delta) and nothing is flat
    assert np.ptp(tr.window[1]) > 1e-2


def test_loop_rejects_no_delay() -> None:
    with pytest.raises(ValueError):
        euler_loop(Params(tau=0.0), 1e-3, 1.0)
