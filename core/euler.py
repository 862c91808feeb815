"""Forward Euler, exactly as the paper integrated eqs. 6a-6e (Section 3, dt = 1e-3).

The delayed m_x(t - tau) is read from a ring buffer of the last N = tau/dt values of m_x.
The buffer starts filled with the history before t = 0 (core.history: by default the
constant m_x(t) = delta of eq. 19; see core.solve for why that is the default).

With ``lyap`` the kernel co-iterates the tangent-linear map of this same Euler map (the
exact derivative of the discrete map), with its own ring buffer, for lambda_max.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from core.model import JIT, rhs, rhs_tangent
from core.recording import blown_up, hand_over, keep_lowest, lowest, renormalise, sample


@njit(**JIT)
def euler(coef, dt, n_delay, n_steps, win, win_start, win_stride, win_jump, win_resume, trace, trace_stride,
          lyap, renorm_steps, logs, init, hx, final, real):
    """Integrate n_steps Euler steps; return the number of steps done (< n_steps on blow-up).

    coef: [a, q, F1, k, d, delta] (core.model.coefficients). n_delay = tau/dt (0: no delay).
    win, trace: (5, n) outputs for the samplers. logs: log-growth of the tangent per
    renormalisation (every renorm_steps steps), filled only if lyap. init: the five
    variables at t = 0; hx: m_x before it at t = -tau + j dt / 2, j = 0..2N (core.history;
    Euler reads the even j). final (5 + N): written at the end, the five variables and
    m_x at t_end - tau + j dt, j = 0..N-1 (what a warm start hands over). real (4): written
    at the end or blow-up, the minima of s_x, s_y and s_x s_y - u^2 over the states of every
    step (0 to the last, the initial and final included) and the first step at which one
    fell below -core.closure.REALISABLE_TOL, -1 if none (core.recording.lowest).
    """
    a, q, f1, k, d = coef[0], coef[1], coef[2], coef[3], coef[4]
    m_x, m_y, s_x, s_y, u = init[0], init[1], init[2], init[3], init[4]  # (19)
    hist = np.empty(n_delay)           # m_x over (t - tau, t]
    for j in range(n_delay):
        hist[j] = hx[2 * j]            # the history, m_x(-tau + j dt)
    e_hist = np.zeros((1, n_delay))    # tangent m_x history
    e_x, e_y, e_sx, e_sy, e_u = 0.0, 1.0, 1.0, 1.0, 1.0
    pos = 0
    next_w, i_w, next_t, i_t = win_start, 0, 0, 0
    next_r, i_r = renorm_steps, 0
    lo_x = lo_y = lo_d = np.inf         # realisability: running minima (lowest)
    first = -1
    for n in range(n_steps):
        lo_x, lo_y, lo_d, first = lowest(lo_x, lo_y, lo_d, first, n, s_x, s_y, u)
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
            keep_lowest(real, lo_x, lo_y, lo_d, first)
            return n + 1
        if lyap and n + 1 == next_r:
            logs[i_r], e_x, e_y, e_sx, e_sy, e_u = renormalise(e_x, e_y, e_sx, e_sy, e_u, e_hist,
                                                                     e_hist.shape[1], dt)
            i_r += 1
            next_r += renorm_steps
    sample(n_steps, next_w, i_w, win_stride, win_jump, win_resume, win, m_x, m_y, s_x, s_y, u)
    sample(n_steps, next_t, i_t, trace_stride, -1, 0, trace, m_x, m_y, s_x, s_y, u)
    lo_x, lo_y, lo_d, first = lowest(lo_x, lo_y, lo_d, first, n_steps, s_x, s_y, u)
    keep_lowest(real, lo_x, lo_y, lo_d, first)
    hand_over(final, m_x, m_y, s_x, s_y, u, hist, pos)
    return n_steps
