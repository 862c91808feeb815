"""Classical RK4 for eqs. 6a-6e, with the delayed m_x from cubic Hermite interpolation.

tau = N dt exactly (core.solve adjusts dt), so the stage times t_n - tau and
t_n + dt - tau fall on stored grid points and only the half step needs interpolating.
The Hermite slope of m_x is m_y itself (eq. 6a), so the interpolant is 4th-order
accurate without any finite differences:
    m_x(t_j + dt/2) = (x_j + x_{j+1}) / 2 + dt (y_j - y_{j+1}) / 8.

For t_n + dt - tau <= 0 every delayed value is read from the history before t = 0, given
at every half step (core.history: by default the constant delta of eq. 19). We do not
interpolate across t = 0: the constant history has slope 0 while m_y(0) = delta, and a
Hermite cubic through that kink would cost a whole order of accuracy.

With ``lyap`` the kernel co-iterates the tangent-linear map of the same RK4 stages, with
Hermite-interpolated tangent history, which is the exact derivative of the discrete map.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from core.model import JIT, rhs, rhs_tangent
from core.recording import blown_up, hand_over, keep_lowest, lowest, renormalise, sample


@njit(**JIT)
def hermite_mid(x0, x1, y0, y1, dt):
    """m_x halfway between two grid points, from values x and slopes y = dm_x/dt."""
    return 0.5 * (x0 + x1) + 0.125 * dt * (y0 - y1)


@njit(**JIT)
def rk4(coef, dt, n_delay, n_steps, win, win_start, win_stride, win_jump, win_resume, trace, trace_stride,
        lyap, renorm_steps, logs, init, hx, final, real):
    """Integrate n_steps RK4 steps; return the number of steps done (< n_steps on blow-up).

    Arguments as core.euler.euler (RK4 reads every half step of hx). The ring buffers hold
    (m_x, m_y) at steps n-N..n.
    """
    a, q, f1, k, d = coef[0], coef[1], coef[2], coef[3], coef[4]
    h = 0.5 * dt
    m_x, m_y, s_x, s_y, u = init[0], init[1], init[2], init[3], init[4]  # (19)
    size = n_delay + 1
    hist = np.empty((2, size))         # rows: m_x, m_y
    e_hist = np.zeros((2, size))       # their tangents
    e_x, e_y, e_sx, e_sy, e_u = 0.0, 1.0, 1.0, 1.0, 1.0
    pos = 0                            # where step n is written
    next_w, i_w, next_t, i_t = win_start, 0, 0, 0
    next_r, i_r = renorm_steps, 0
    lo_x = lo_y = lo_d = np.inf         # realisability: running minima (lowest)
    first = -1
    for n in range(n_steps):
        lo_x, lo_y, lo_d, first = lowest(lo_x, lo_y, lo_d, first, n, s_x, s_y, u)
        next_w, i_w = sample(n, next_w, i_w, win_stride, win_jump, win_resume, win, m_x, m_y, s_x, s_y, u)
        next_t, i_t = sample(n, next_t, i_t, trace_stride, -1, 0, trace, m_x, m_y, s_x, s_y, u)
        hist[0, pos] = m_x
        hist[1, pos] = m_y
        e_hist[0, pos] = e_x
        e_hist[1, pos] = e_y
        old = pos + 1 if pos + 1 < size else 0   # step n - N
        nxt = old + 1 if old + 1 < size else 0   # step n - N + 1
        pos = old
        if n_delay == 0:
            # no delay: handled below by using each stage's own m_x
            x0 = xh = x1 = ex0 = exh = ex1 = 0.0
        elif n < n_delay:
            # t_n + dt - tau <= 0: the history (tangent 0)
            x0, xh, x1 = hx[2 * n], hx[2 * n + 1], hx[2 * n + 2]
            ex0 = exh = ex1 = 0.0
        else:
            x0, x1 = hist[0, old], hist[0, nxt]
            xh = hermite_mid(x0, x1, hist[1, old], hist[1, nxt], dt)
            ex0, ex1 = e_hist[0, old], e_hist[0, nxt]
            exh = hermite_mid(ex0, ex1, e_hist[1, old], e_hist[1, nxt], dt)
        # stage 1
        xs, ys, sxs, sys, us = m_x, m_y, s_x, s_y, u
        k1 = rhs(xs, ys, sxs, sys, us, xs if n_delay == 0 else x0, a, q, f1, k, d)
        # stage 2
        x2, y2, sx2, sy2, u2 = m_x + h * k1[0], m_y + h * k1[1], s_x + h * k1[2], s_y + h * k1[3], u + h * k1[4]
        k2 = rhs(x2, y2, sx2, sy2, u2, x2 if n_delay == 0 else xh, a, q, f1, k, d)
        # stage 3
        x3, y3, sx3, sy3, u3 = m_x + h * k2[0], m_y + h * k2[1], s_x + h * k2[2], s_y + h * k2[3], u + h * k2[4]
        k3 = rhs(x3, y3, sx3, sy3, u3, x3 if n_delay == 0 else xh, a, q, f1, k, d)
        # stage 4
        x4, y4, sx4, sy4, u4 = m_x + dt * k3[0], m_y + dt * k3[1], s_x + dt * k3[2], s_y + dt * k3[3], u + dt * k3[4]
        k4 = rhs(x4, y4, sx4, sy4, u4, x4 if n_delay == 0 else x1, a, q, f1, k, d)
        if lyap:
            # the same stages, differentiated: K_i = J(X_i) (e + c_i dt K_{i-1}) + J_tau e_tau
            t1 = rhs_tangent(ys, sys, us, e_x, e_y, e_sx, e_sy, e_u, e_x if n_delay == 0 else ex0, a, q, f1, k)
            g = (e_x + h * t1[0], e_y + h * t1[1], e_sx + h * t1[2], e_sy + h * t1[3], e_u + h * t1[4])
            t2 = rhs_tangent(y2, sy2, u2, g[0], g[1], g[2], g[3], g[4], g[0] if n_delay == 0 else exh, a, q, f1, k)
            g = (e_x + h * t2[0], e_y + h * t2[1], e_sx + h * t2[2], e_sy + h * t2[3], e_u + h * t2[4])
            t3 = rhs_tangent(y3, sy3, u3, g[0], g[1], g[2], g[3], g[4], g[0] if n_delay == 0 else exh, a, q, f1, k)
            g = (e_x + dt * t3[0], e_y + dt * t3[1], e_sx + dt * t3[2], e_sy + dt * t3[3], e_u + dt * t3[4])
            t4 = rhs_tangent(y4, sy4, u4, g[0], g[1], g[2], g[3], g[4], g[0] if n_delay == 0 else ex1, a, q, f1, k)
            w = dt / 6.0
            e_x += w * (t1[0] + 2.0 * (t2[0] + t3[0]) + t4[0])
            e_y += w * (t1[1] + 2.0 * (t2[1] + t3[1]) + t4[1])
            e_sx += w * (t1[2] + 2.0 * (t2[2] + t3[2]) + t4[2])
            e_sy += w * (t1[3] + 2.0 * (t2[3] + t3[3]) + t4[3])
            e_u += w * (t1[4] + 2.0 * (t2[4] + t3[4]) + t4[4])
        w = dt / 6.0
        m_x += w * (k1[0] + 2.0 * (k2[0] + k3[0]) + k4[0])
        m_y += w * (k1[1] + 2.0 * (k2[1] + k3[1]) + k4[1])
        s_x += w * (k1[2] + 2.0 * (k2[2] + k3[2]) + k4[2])
        s_y += w * (k1[3] + 2.0 * (k2[3] + k3[3]) + k4[3])
        u += w * (k1[4] + 2.0 * (k2[4] + k3[4]) + k4[4])
        if blown_up(m_y, s_y):
            keep_lowest(real, lo_x, lo_y, lo_d, first)
            return n + 1
        if lyap and n + 1 == next_r:
            # the slot at pos (step n - N) is stale: make it vanish from the norm
            e_hist[0, pos] = e_x
            e_hist[1, pos] = 0.0
            logs[i_r], e_x, e_y, e_sx, e_sy, e_u = renormalise(e_x, e_y, e_sx, e_sy, e_u, e_hist,
                                                                     e_hist.shape[1], dt)
            i_r += 1
            next_r += renorm_steps
    sample(n_steps, next_w, i_w, win_stride, win_jump, win_resume, win, m_x, m_y, s_x, s_y, u)
    sample(n_steps, next_t, i_t, trace_stride, -1, 0, trace, m_x, m_y, s_x, s_y, u)
    lo_x, lo_y, lo_d, first = lowest(lo_x, lo_y, lo_d, first, n_steps, s_x, s_y, u)
    keep_lowest(real, lo_x, lo_y, lo_d, first)
    # pos is the slot of step n_steps - 1 - N: steps n_steps - N.. follow it
    hand_over(final, m_x, m_y, s_x, s_y, u, hist[0], pos + 1 if pos + 1 < size else 0)
    return n_steps
