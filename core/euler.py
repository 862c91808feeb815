"""Forward Euler, exactly as the paper integrated eqs. 6a-6e (Section 3, dt = 1e-3).

The delayed m_x(t - tau) is read from a ring buffer of the last N = tau/dt values of m_x.
The buffer starts filled with the history before t = 0 (core.history: by default the
constant m_x(t) = delta of eq. 19; see core.solve for why that is the default).

With ``lyap`` the kernel co-iterates the tangent-linear map of this same Euler map (the
exact derivative of the discrete map), with its own ring buffer, for lambda_max.

The step itself (euler_step, euler_tangent_step) is shared with the spectrum's kernel
(core.tangents), so that both integrate one discrete map. numba inlines it into each
kernel before LLVM sees the code (inline="always"), so every kernel compiles the step as
if written in its loop, with the same fused multiply-adds.
"""

from __future__ import annotations

from numba import njit

from core import chunk_state as cs
from core.model import JIT, rhs, rhs_tangent
from core.recording import blown_up, keep, lowest, renormalise, sample


@njit(inline="always", **JIT)
def euler_step(m_x, m_y, s_x, s_y, u, m_x_tau, dt, a, q, f1, k, d):
    """One Euler step of eqs. 6a-6e from the state and the delayed m_x."""
    f = rhs(m_x, m_y, s_x, s_y, u, m_x_tau, a, q, f1, k, d)
    return m_x + dt * f[0], m_y + dt * f[1], s_x + dt * f[2], s_y + dt * f[3], u + dt * f[4]


@njit(inline="always", **JIT)
def euler_tangent_step(m_y, s_y, u, e_x, e_y, e_sx, e_sy, e_u, e_x_tau, dt, a, q, f1, k):
    """The derivative of euler_step at the state applied to the tangent e (and its delayed
    e_x): the same step on the variational equation."""
    f = rhs_tangent(m_y, s_y, u, e_x, e_y, e_sx, e_sy, e_u, e_x_tau, a, q, f1, k)
    return e_x + dt * f[0], e_y + dt * f[1], e_sx + dt * f[2], e_sy + dt * f[3], e_u + dt * f[4]


@njit(**JIT)
def euler(coef, dt, n_delay, lyap, plan, hx, now, counts, ring, e_ring, win, trace, logs):
    """Euler steps from step counts[N_AT] to plan[END]; return the steps done (plan[END],
    or n + 1 after a blow-up at step n).

    The contract, its arguments and the state arrays' layout: core.methods and
    core.chunk_state. The ring (1, N) holds m_x over (t - tau, t]: slot POS holds
    m_x(t - tau), where m_x(t) goes (read from hx[0::2] at the start: ChunkState.start).
    hx itself is not read.
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
    hist = ring[0]                     # m_x over (t - tau, t]
    for n in range(n0, end):
        lo_x, lo_y, lo_d, first = lowest(lo_x, lo_y, lo_d, first, n, s_x, s_y, u)
        next_w, i_w = sample(n, next_w, i_w, w_stride, w_jump, w_resume, win, m_x, m_y, s_x, s_y, u)
        next_t, i_t = sample(n, next_t, i_t, t_stride, -1, 0, trace, m_x, m_y, s_x, s_y, u)
        if n_delay > 0:
            m_x_tau = hist[pos]
            hist[pos] = m_x
            e_x_tau = e_ring[0, pos]
            e_ring[0, pos] = e_x
            pos += 1
            if pos == n_delay:
                pos = 0
        else:
            m_x_tau = m_x
            e_x_tau = e_x
        if lyap:
            e_x, e_y, e_sx, e_sy, e_u = euler_tangent_step(m_y, s_y, u, e_x, e_y, e_sx, e_sy, e_u,
                                                           e_x_tau, dt, a, q, f1, k)
        m_x, m_y, s_x, s_y, u = euler_step(m_x, m_y, s_x, s_y, u, m_x_tau, dt, a, q, f1, k, d)
        if blown_up(m_y, s_y):
            counts[cs.BLOWN] = n
            keep(now, counts, m_x, m_y, s_x, s_y, u, e_x, e_y, e_sx, e_sy, e_u, lo_x, lo_y, lo_d,
                 n + 1, pos, next_w, i_w, next_t, i_t, next_r, i_r, first)
            return n + 1
        if lyap and n + 1 == next_r:
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
