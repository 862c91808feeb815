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
The step itself (rk4_step, rk4_tangent_step) is shared with the spectrum's kernel
(core.tangents), so that both integrate one discrete map. numba inlines it into each
kernel before LLVM sees the code (inline="always"): as separate functions inlined by LLVM,
the tangent's multiply-adds fused differently, and lambda_max's logs moved by ~1e-15.
"""

from __future__ import annotations

from numba import njit

from core import chunk_state as cs
from core.model import JIT, rhs, rhs_tangent
from core.recording import blown_up, keep, lowest, renormalise, sample


@njit(**JIT)
def hermite_mid(x0, x1, y0, y1, dt):
    """m_x halfway between two grid points, from values x and slopes y = dm_x/dt."""
    return 0.5 * (x0 + x1) + 0.125 * dt * (y0 - y1)


@njit(inline="always", **JIT)
def rk4_step(m_x, m_y, s_x, s_y, u, x0, xh, x1, no_delay, dt, a, q, f1, k, d):
    """One RK4 step of eqs. 6a-6e, the delayed m_x being x0, xh, x1 at the step's start,
    middle and end (each stage's own m_x if no_delay). Returns the new state and the
    (m_y, s_y, u) of stages 2-4, which the tangent's step needs."""
    h = 0.5 * dt
    k1 = rhs(m_x, m_y, s_x, s_y, u, m_x if no_delay else x0, a, q, f1, k, d)
    x2, y2, sx2, sy2, u2 = m_x + h * k1[0], m_y + h * k1[1], s_x + h * k1[2], s_y + h * k1[3], u + h * k1[4]
    k2 = rhs(x2, y2, sx2, sy2, u2, x2 if no_delay else xh, a, q, f1, k, d)
    x3, y3, sx3, sy3, u3 = m_x + h * k2[0], m_y + h * k2[1], s_x + h * k2[2], s_y + h * k2[3], u + h * k2[4]
    k3 = rhs(x3, y3, sx3, sy3, u3, x3 if no_delay else xh, a, q, f1, k, d)
    x4, y4, sx4, sy4, u4 = m_x + dt * k3[0], m_y + dt * k3[1], s_x + dt * k3[2], s_y + dt * k3[3], u + dt * k3[4]
    k4 = rhs(x4, y4, sx4, sy4, u4, x4 if no_delay else x1, a, q, f1, k, d)
    w = dt / 6.0
    return (m_x + w * (k1[0] + 2.0 * (k2[0] + k3[0]) + k4[0]),
            m_y + w * (k1[1] + 2.0 * (k2[1] + k3[1]) + k4[1]),
            s_x + w * (k1[2] + 2.0 * (k2[2] + k3[2]) + k4[2]),
            s_y + w * (k1[3] + 2.0 * (k2[3] + k3[3]) + k4[3]),
            u + w * (k1[4] + 2.0 * (k2[4] + k3[4]) + k4[4]),
            (y2, sy2, u2, y3, sy3, u3, y4, sy4, u4))


@njit(inline="always", **JIT)
def rk4_tangent_step(m_y, s_y, u, stages, e_x, e_y, e_sx, e_sy, e_u, ex0, exh, ex1, no_delay, dt,
                     a, q, f1, k):
    """The derivative of rk4_step at the state (m_y, s_y, u and the stages it returned)
    applied to the tangent e, whose delayed e_x is ex0, exh, ex1: the same stages,
    differentiated, K_i = J(X_i) (e + c_i dt K_{i-1}) + J_tau e_tau."""
    h = 0.5 * dt
    y2, sy2, u2, y3, sy3, u3, y4, sy4, u4 = stages
    t1 = rhs_tangent(m_y, s_y, u, e_x, e_y, e_sx, e_sy, e_u, e_x if no_delay else ex0, a, q, f1, k)
    g = (e_x + h * t1[0], e_y + h * t1[1], e_sx + h * t1[2], e_sy + h * t1[3], e_u + h * t1[4])
    t2 = rhs_tangent(y2, sy2, u2, g[0], g[1], g[2], g[3], g[4], g[0] if no_delay else exh, a, q, f1, k)
    g = (e_x + h * t2[0], e_y + h * t2[1], e_sx + h * t2[2], e_sy + h * t2[3], e_u + h * t2[4])
    t3 = rhs_tangent(y3, sy3, u3, g[0], g[1], g[2], g[3], g[4], g[0] if no_delay else exh, a, q, f1, k)
    g = (e_x + dt * t3[0], e_y + dt * t3[1], e_sx + dt * t3[2], e_sy + dt * t3[3], e_u + dt * t3[4])
    t4 = rhs_tangent(y4, sy4, u4, g[0], g[1], g[2], g[3], g[4], g[0] if no_delay else ex1, a, q, f1, k)
    w = dt / 6.0
    return (e_x + w * (t1[0] + 2.0 * (t2[0] + t3[0]) + t4[0]),
            e_y + w * (t1[1] + 2.0 * (t2[1] + t3[1]) + t4[1]),
            e_sx + w * (t1[2] + 2.0 * (t2[2] + t3[2]) + t4[2]),
            e_sy + w * (t1[3] + 2.0 * (t2[3] + t3[3]) + t4[3]),
            e_u + w * (t1[4] + 2.0 * (t2[4] + t3[4]) + t4[4]))


@njit(**JIT)
def rk4(coef, dt, n_delay, lyap, plan, hx, now, counts, ring, e_ring, win, trace, logs):
    """RK4 steps from step counts[N_AT] to plan[END]; return the steps done (plan[END], or
    n + 1 after a blow-up at step n).

    The contract, its arguments and the state arrays' layout: core.methods and
    core.chunk_state. RK4 reads every half step of hx while t + dt - tau <= 0. The rings
    (2, N + 1) hold (m_x, m_y) at steps n - N - 1..n - 1: slot POS is where step n goes.
    """
    a, q, f1, k, d = coef[0], coef[1], coef[2], coef[3], coef[4]
    m_x, m_y, s_x, s_y, u = now[cs.M_X], now[cs.M_Y], now[cs.S_X], now[cs.S_Y], now[cs.U]
    e_x, e_y, e_sx, e_sy, e_u = now[cs.E_X], now[cs.E_Y], now[cs.E_SX], now[cs.E_SY], now[cs.E_U]
    lo_x, lo_y, lo_d = now[cs.LO_X], now[cs.LO_Y], now[cs.LO_D]   # realisability: running minima
    n0, pos, first = counts[cs.N_AT], counts[cs.POS], counts[cs.FIRST]
    next_w, i_w, next_t, i_t = counts[cs.NEXT_W], counts[cs.I_W], counts[cs.NEXT_T], counts[cs.I_T]
    next_r, i_r = counts[cs.NEXT_R], counts[cs.I_R]
    end, w_stride, w_jump, w_resume = plan[cs.END], plan[cs.WIN_STRIDE], plan[cs.WIN_JUMP], plan[cs.WIN_RESUME]
    t_stride, renorm_steps = plan[cs.TRACE_STRIDE], plan[cs.RENORM_STEPS]
    size = n_delay + 1
    no_delay = n_delay == 0
    for n in range(n0, end):
        lo_x, lo_y, lo_d, first = lowest(lo_x, lo_y, lo_d, first, n, s_x, s_y, u)
        next_w, i_w = sample(n, next_w, i_w, w_stride, w_jump, w_resume, win, m_x, m_y, s_x, s_y, u)
        next_t, i_t = sample(n, next_t, i_t, t_stride, -1, 0, trace, m_x, m_y, s_x, s_y, u)
        ring[0, pos] = m_x
        ring[1, pos] = m_y
        e_ring[0, pos] = e_x
        e_ring[1, pos] = e_y
        old = pos + 1 if pos + 1 < size else 0   # step n - N
        nxt = old + 1 if old + 1 < size else 0   # step n - N + 1
        pos = old
        if no_delay:
            # no delay: rk4_step uses each stage's own m_x
            x0 = xh = x1 = ex0 = exh = ex1 = 0.0
        elif n < n_delay:
            # t_n + dt - tau <= 0: the history (tangent 0)
            x0, xh, x1 = hx[2 * n], hx[2 * n + 1], hx[2 * n + 2]
            ex0 = exh = ex1 = 0.0
        else:
            x0, x1 = ring[0, old], ring[0, nxt]
            xh = hermite_mid(x0, x1, ring[1, old], ring[1, nxt], dt)
            ex0, ex1 = e_ring[0, old], e_ring[0, nxt]
            exh = hermite_mid(ex0, ex1, e_ring[1, old], e_ring[1, nxt], dt)
        x_new, y_new, sx_new, sy_new, u_new, stages = rk4_step(m_x, m_y, s_x, s_y, u, x0, xh, x1,
                                                              no_delay, dt, a, q, f1, k, d)
        if lyap:
            e_x, e_y, e_sx, e_sy, e_u = rk4_tangent_step(m_y, s_y, u, stages, e_x, e_y, e_sx, e_sy,
                                                         e_u, ex0, exh, ex1, no_delay, dt, a, q, f1, k)
        m_x, m_y, s_x, s_y, u = x_new, y_new, sx_new, sy_new, u_new
        if blown_up(m_y, s_y):
            counts[cs.BLOWN] = n
            keep(now, counts, m_x, m_y, s_x, s_y, u, e_x, e_y, e_sx, e_sy, e_u, lo_x, lo_y, lo_d,
                 n + 1, pos, next_w, i_w, next_t, i_t, next_r, i_r, first)
            return n + 1
        if lyap and n + 1 == next_r:
            # the slot at pos (step n - N) is stale: make it vanish from the norm
            e_ring[0, pos] = e_x
            e_ring[1, pos] = 0.0
            logs[i_r], e_x, e_y, e_sx, e_sy, e_u = renormalise(e_x, e_y, e_sx, e_sy, e_u, e_ring,
                                                                     e_ring.shape[1], dt)
            i_r += 1
            next_r += renorm_steps
    # the state it stops at: recorded again by a call that continues it (idempotent)
    next_w, i_w = sample(end, next_w, i_w, w_stride, w_jump, w_resume, win, m_x, m_y, s_x, s_y, u)
    next_t, i_t = sample(end, next_t, i_t, t_stride, -1, 0, trace, m_x, m_y, s_x, s_y, u)
    lo_x, lo_y, lo_d, first = lowest(lo_x, lo_y, lo_d, first, end, s_x, s_y, u)
    keep(now, counts, m_x, m_y, s_x, s_y, u, e_x, e_y, e_sx, e_sy, e_u, lo_x, lo_y, lo_d,
         end, pos, next_w, i_w, next_t, i_t, next_r, i_r, first)
    return end
