"""A plain Python/NumPy Euler loop for eqs. 6a-6e: the stand-in for the paper's MATLAB loop.

This is how a researcher writes the model without a compiler: one Python iteration per
time step, the five variables as Python floats, the delayed m_x from a ring buffer of the
last N values, the right-hand side typed out from the paper. It is deliberately *not*
vectorised or compiled; ``benchmarks/bench_peers.py`` times it against slopetui's kernels.
The ring buffer is a ``collections.deque`` of Python floats rather than a NumPy array:
indexing a NumPy array from Python returns NumPy scalars, whose arithmetic is slower than
Python floats', and the stand-in should be a fair loop, not a clumsy one. NumPy only holds
the output samples.

The scheme is exactly core.euler's, so the two integrate the same discrete map (checked
to round-off by tests/unit/test_numpy_loop.py):
  * the grid of core.solve: N = ceil(tau / dt) slots and the effective step dt' = tau / N,
    so that m_x(t_n - tau) = m_x at step n - N falls on the grid;
  * the constant history m_x(t) = delta for t <= 0 (the buffer starts full of delta) and
    all five variables = delta at t = 0 (eq. 19);
  * at each step, take the value stored N steps ago out of the buffer and put the current
    m_x in (FIFO of length N: the same ring-buffer delay as core.euler).
Only the arithmetic differs: the paper's form of the equations instead of core.model's
Horner form, and no fused multiply-adds, so results agree to round-off, not bit for bit.

Times are model time units, as everywhere in slopetui.
"""

from __future__ import annotations

import math
from collections import deque

import numpy as np

from core.params import Params


def euler_loop(p: Params, dt: float, t_end: float, stride: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Integrate from t = 0 to t_end with forward Euler; sample every ``stride`` steps.

    Returns (t, states): the sample times (steps 0, stride, 2 stride, ... <= n_steps) and a
    (5, n) array with rows m_x, m_y, s_x, s_y, u. Requires tau > 0 (the delayed model).
    """
    if p.tau <= 0.0:
        raise ValueError("euler_loop needs tau > 0")
    n_delay = math.ceil(p.tau / dt - 1e-9)  # the grid of core.solve.make_grid
    h = p.tau / n_delay
    n_steps = math.ceil(t_end / h - 1e-9)
    a, b, c, d, k, v = p.a, p.b, p.c, p.d, p.k, p.v
    f1 = 3.0 * a * v * v - 2.0 * b * v + c  # F'(v), the bracket's constant part
    q = 3.0 * a * v - b

    n_samples = n_steps // stride + 1
    out = np.empty((5, n_samples))
    hist = deque([p.delta] * n_delay)  # m_x over (t - tau, t]; the history is delta
    m_x = m_y = s_x = s_y = u = p.delta  # (19)
    for n in range(n_steps):
        if n % stride == 0:
            out[:, n // stride] = (m_x, m_y, s_x, s_y, u)
        m_x_tau = hist.popleft()  # m_x at step n - N
        hist.append(m_x)
        g = f1 + 2.0 * q * m_y + 3.0 * a * (m_y * m_y + s_y)
        dmx = m_y                                                              # (6a)
        dmy = (-f1 * m_y - q * m_y * m_y - a * m_y * m_y * m_y
               - q * s_y - 3.0 * a * m_y * s_y + k * (m_x_tau - m_x))          # (6b)
        dsx = 2.0 * u                                                          # (6c)
        dsy = -2.0 * s_y * g - 2.0 * k * u + 2.0 * d                           # (6d)
        du = -u * g - k * s_x + s_y                                            # (6e)
        m_x += h * dmx
        m_y += h * dmy
        s_x += h * dsx
        s_y += h * dsy
        u += h * du
    if n_steps % stride == 0:
        out[:, n_steps // stride] = (m_x, m_y, s_x, s_y, u)
    return stride * h * np.arange(n_samples), out
