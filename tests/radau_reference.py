"""An independent reference for eqs. 6a-6e: scipy's Radau IIA (order 5, stiffly accurate),
integrated by the method of steps.

On [j tau, (j + 1) tau] the delayed m_x(t - tau) is a known function, the previous
interval's dense output (the constant history m_x = delta for j = 0, eq. 19), so each
interval is an ODE. Nothing here comes from core: the right-hand side is written again
from the paper, so a slip in core.model would show up as a disagreement.

Used by tests/unit/test_stiff_solver.py; scipy is a test dependency only.
"""

from __future__ import annotations

from bisect import bisect_left
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

#: Radau's tolerances: its error at these is far below the O(dt) of the kernels tested.
RTOL, ATOL = 1e-8, 1e-10


@dataclass
class Reference:
    """The Radau solution on [0, t_end] (or up to ``t_fail``, if the solver gave up)."""

    pieces: list        # OdeSolution of each delay interval, in order
    starts: np.ndarray  # start time of each piece
    t_end: float        # where the solution ends (t_fail if it failed)
    failed: bool        # Radau stopped (step size underflow: a true divergence)
    min_s_y: float      # min s_y over Radau's own steps
    min_det: float      # min s_x s_y - u^2 over Radau's own steps

    def __call__(self, t: np.ndarray | float) -> np.ndarray:
        """The five variables (m_x, m_y, s_x, s_y, u) at time(s) t, shape (5, len(t))."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        idx = np.clip(np.searchsorted(self.starts, t, side="right") - 1, 0, len(self.pieces) - 1)
        out = np.empty((5, t.size))
        for i in np.unique(idx):
            sel = idx == i
            out[:, sel] = self.pieces[i](t[sel])
        return out


def rhs(t, z, m_x_tau, a, b, c, d, k, v):
    """Eqs. 6a-6e, from the paper."""
    m_x, m_y, s_x, s_y, u = z.tolist()
    f1 = 3 * a * v**2 - 2 * b * v + c
    q = 3 * a * v - b
    g = f1 + 2 * q * m_y + 3 * a * (m_y**2 + s_y)
    return np.array([
        m_y,                                                                         # (6a)
        -f1 * m_y - q * m_y**2 - a * m_y**3 - q * s_y - 3 * a * m_y * s_y + k * (m_x_tau(t) - m_x),  # (6b)
        2 * u,                                                                       # (6c)
        -2 * s_y * g - 2 * k * u + 2 * d,                                            # (6d)
        -u * g - k * s_x + s_y,                                                      # (6e)
    ])


def jac(t, z, a, b, c, k, v):
    """d(6a-6e)/dz at fixed m_x(t - tau) (Radau's Newton matrix)."""
    _, m_y, _, s_y, u = z.tolist()
    f1 = 3 * a * v**2 - 2 * b * v + c
    q = 3 * a * v - b
    g = f1 + 2 * q * m_y + 3 * a * (m_y**2 + s_y)
    g_y, g_s = 2 * q + 6 * a * m_y, 3 * a
    return np.array([
        [0.0, 1.0, 0.0, 0.0, 0.0],
        [-k, -g, 0.0, -(q + 3 * a * m_y), 0.0],
        [0.0, 0.0, 0.0, 0.0, 2.0],
        [0.0, -2 * s_y * g_y, 0.0, -2 * g - 2 * s_y * g_s, -2 * k],
        [0.0, -u * g_y, -k, 1.0 - u * g_s, -g],
    ])


def radau(a: float = 3.2, b: float = 7.2, c: float = 4.8, d: float = 1e-4, k: float = 10.0,
          v: float = 0.1, tau: float = 10.0, delta: float = 0.1, t_end: float = 100.0,
          rtol: float = RTOL, atol: float = ATOL, history=None) -> Reference:
    """Eqs. 6a-6e from eq. 19, to t_end, with ``history`` (t -> m_x(t) for t <= 0; by
    default the constant history m_x = delta)."""
    z = np.full(5, float(delta))                         # (19)
    pieces, starts = [], []
    min_s_y, min_det = np.inf, np.inf
    if history is None:
        history = lambda t: np.full_like(np.asarray(t, dtype=float), delta)  # noqa: E731
    else:
        given = history
        history = lambda t: given(t - tau)  # noqa: E731 - m_x(t - tau) on [0, tau]
    t0, failed = 0.0, False
    while t0 < t_end * (1 - 1e-14):
        t1 = min(t0 + tau, t_end)
        hist = history
        sol = solve_ivp(lambda t, y, h=hist: rhs(t, y, h, a, b, c, d, k, v), (t0, t1), z,
                        method="Radau", rtol=rtol, atol=atol, dense_output=True,
                        jac=lambda t, y: jac(t, y, a, b, c, k, v))
        if sol.t.size > 1:
            pieces.append(sol.sol)
            starts.append(t0)
            ys = sol.y
            min_s_y = min(min_s_y, float(ys[3].min()))
            min_det = min(min_det, float((ys[2] * ys[3] - ys[4] ** 2).min()))
        if sol.status != 0:
            failed, t_end = True, float(sol.t[-1])
            break
        z = sol.y[:, -1]
        t0 = t1
        # the next interval's delayed m_x is this interval's m_x, shifted by tau
        history = _shifted(sol.sol, tau)
    return Reference(pieces, np.array(starts), t_end, failed, min_s_y, min_det)


def _shifted(sol, tau: float):
    """t -> m_x(t - tau) from one interval's dense output: Radau's collocation polynomial
    of the step holding t - tau (scipy's RadauDenseOutput), its m_x row only, in plain
    floats (the generic call costs ~25 us, a third of the whole reference's time)."""
    ts = sol.ts.tolist()
    steps = [(i.t_old, i.h, i.y_old[0], i.Q[0].tolist()) for i in sol.interpolants]

    def m_x_tau(t: float) -> float:
        s = t - tau
        t_old, h, x_old, q = steps[min(max(bisect_left(ts, s) - 1, 0), len(steps) - 1)]
        x = (s - t_old) / h
        acc, p = x_old, x
        for c in q:
            acc += c * p
            p *= x
        return acc

    return m_x_tau
