"""Forward Euler, exactly as the paper integrated eqs. 6a-6e (Section 3, dt = 1e-3).

The delayed m_x(t - tau) is read from a ring buffer of the last N = tau/dt values of m_x.
The buffer starts filled with delta, which *is* the initial history m_x(t) = delta for
t <= 0 (eq. 19; see core.solve for why we chose a constant history).

With ``lyap`` the kernel co-iterates the tangent-linear map of this same Euler map (the
exact derivative of the discrete map), with its own ring buffer, for lambda_max.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from core.model import JIT, rhs, rhs_tangent
from core.recording import blown_up, renormalise, sample


@njit(**JIT)
def euler(coef, dt, n_delay, n_steps, win, win_start, win_stride, win_jump, win_resume, trace, trace_stride,
          lyap, renorm_steps, logs):
    """Integrate n_steps Euler steps; return the number of steps done (< n_steps on blow-up).

    coef: [a, q, F1, k, d, delta] (core.model.coefficients). n_delay = tau/dt (0: no delay).
    win, trace: (5, n) outputs for the samplers. logs: log-growth of the tangent per
    renormalisation (every renorm_steps steps), filled only if lyap.
    """
    a, q, f1, k, d, delta = coef[0], coef[1], coef[2], coef[3], coef[4], coef[5]
    m_x = m_y = s_x = s_y = u = delta  # (19)
    hist = np.full(n_delay, delta)     # m_x over (t - tau, t]; history = delta
    e_hist = np.zeros((1, n_delay))    # tangent m_x history
    e_x, e_y, e_sx, e_sy, e_u = 0.0, 1.0, 1.0, 1.0, 1.0
    pos = 0
    next_w, i_w, next_t, i_t = win_start, 0, 0, 0
    next_r, i_r = renorm_steps, 0
    for n in range(n_steps):
        next_w, i_w = sample(n, next_w, i_w, win_stride, win_jump, win_resume, win, m_x, m_y, s_x, s_y, u)
        next_t, i_t = sample(n, next_t, i_t, trace_stride, -1, 0, trace, m_x, m_y, s_x, s_y, u)
        if n_delay > 0:
            m_x_tau = hist[pos]
            hist[pos] = m_x
            e_x_tau = e_hist[0, pos]
            e_hist[0, pos] = e_x
            pos += 1
            if pos == n_delay:
                pos = 0
        else:
            m_x_tau = m_x
            e_x_tau = e_x
        if lyap:
            f = rhs_tangent(m_y, s_y, u, e_x, e_y, e_sx, e_sy, e_u, e_x_tau, a, q, f1, k)
            e_x += dt * f[0]
            e_y += dt * f[1]
            e_sx += dt * f[2]
            e_sy += dt * f[3]
            e_u += dt * f[4]
        f = rhs(m_x, m_y, s_x, s_y, u, m_x_tau, a, q, f1, k, d)
        m_x += dt * f[0]
        m_y += dt * f[1]
        s_x += dt * f[2]
        s_y += dt * f[3]
        u += dt * f[4]
        if blown_up(m_y, s_y):
            return n + 1
        if lyap and n + 1 == next_r:
            logs[i_r], e_x, e_y, e_sx, e_sy, e_u = renormalise(e_x, e_y, e_sx, e_sy, e_u, e_hist,
                                                                     e_hist.shape[1], dt)
            i_r += 1
            next_r += renorm_steps
    sample(n_steps, next_w, i_w, win_stride, win_jump, win_resume, win, m_x, m_y, s_x, s_y, u)
    sample(n_steps, next_t, i_t, trace_stride, -1, 0, trace, m_x, m_y, s_x, s_y, u)
    return n_steps
