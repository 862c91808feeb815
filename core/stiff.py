"""A stiff-safe kernel for eqs. 6a-6e: linearly implicit Euler with the decay rate G taken
implicitly (a W-method). It reads step for step beside core.euler.

Why. G = F'(v) + 2(3av - b) m_y + 3a (m_y^2 + s_y) (core.model.damping) is the one fast
rate of the model: d(6b)/dm_y = -G, and (6d), (6e) decay at 2G and G. On the fast sliding
branch of Fig. 7 (a = 0.035, k = 12, tau = 1: m_y = 203.25, G = 1419) Euler at dt = 1e-3
is past its limit dt 2G < 2 and blows up at t = 0.5, although the model rests there. Eq. 19
also starts on a singular covariance (s_x s_y = u^2): the exact s_y then grazes 0 (down to
~2e-5), an explicit step overshoots below 0 (Euler's s_y < 0 right after the start for delta >= 0.01,
the defaults included), and at moderate b and small tau -6a s_y^2 then runs it away (below).

The step. With G frozen at its value at t_n, (6c)-(6e) are the Lyapunov equation
dS/dt = A S + S A^T + D of the covariance S = [[s_x, u], [u, s_y]], A = [[0, 1], [-k, -G]],
D = diag(0, 2d). For z = (m_x, m_y, s_x, s_y, u):
    (I - dt J_W) (z_{n+1} - z_n) = dt f(z_n, m_x(t_n - tau)),
J_W: -G on m_y (the exact d(6b)/dm_y), the Lyapunov operator on (s_x, s_y, u), and (6a)
taken at n + 1 (m_x_{n+1} = m_x_n + dt m_y_{n+1}). Explicit, as in Euler: the delay term
k (m_x,tau - m_x) from the same ring buffer, and how G and the m_y terms of (6b) depend on
the state. W is block-triangular; w_solve solves it by hand with one division.

Properties.
- Consistent, first order: a W-method is order 1 for any W. Measured order 1.00 below.
- Steady states exact: f = 0 gives z_{n+1} = z_n. So does steady sliding on a fast branch
  (d = 0): on the grid m_x,tau - m_x = -N dt m_y = -tau m_y, W has no m_x column, so m_y
  stays on the root of core.params.sliding_branches.
- L-stable on the variance block: for G > 0 the covariance step is implicit Euler on the
  Lyapunov equation, with amplification 1 / (1 - dt mu) -> 0 for its eigenvalues mu
  (2 lambda_1, 2 lambda_2, lambda_1 + lambda_2 of A), whatever dt G.
- Realisable (s_x >= 0, s_y >= 0, s_x s_y >= u^2 at every step). The step is
  S_{n+1} = (I - dt L)^{-1} (S_n + dt D), L S = A S + S A^T. If dt s(L) < 1 (s: spectral
  abscissa), (I - dt L)^{-1} = integral_0^inf e^{-r} e^{r dt L} dr, an average of
  congruences S -> e^{r dt A} S e^{r dt A^T}, so it keeps S positive semidefinite. Now
  s(L) = 2 max Re lambda(A) <= 2 max(-G, 0). Where G < -1/(4 dt) (a runaway's acceleration:
  min G = F' - q^2 / (3a) = -489 at a = 0.035, -571 at a = 0.03) the step is split into
  substeps of -G h <= GROWTH = 1/4. That gives dt s(L) <= 1/2 and keeps 1 + h G, 1 + 2 h G
  >= 1/2. Without the split, dt = 1e-2 at a = 0.03 and 0.035 gives s_y = -290 and -510, and
  the run ends at rest instead of on the branch. With it, those runs end on the branch
  to 3e-9. No rational method of order > 1 is positive for every step (Bolley & Crouzeix,
  RAIRO Anal. Numer. 12, 1978), so first order is the price of this guarantee.
- The cost of positivity is numerical diffusion. The averaging over r spreads a rank-one
  S = v v^T by ~dt |A v|^2 per time unit. Near the singular start that is more than the
  noise 2d = 2e-4: at dt = 1e-3 s_y grazes at ~6e-4 instead of ~2e-5. The transient after
  such a graze converges slowly in dt (table: negative-variance points). The runs still
  reach Radau's attractor: within 6.3e-7 by t = 25, and closer after that.

lambda_max: the tangent is the same W-step (same W, same substeps) applied to the
variational equation (core.model.rhs_tangent), with its own ring buffer and
core.recording.renormalise, as in core.euler. The map's derivative differs from this
only by (d W^{-1} / dz) dt f. That term vanishes at a fixed point, so there lambda_max is the
exponent of the discretised linearisation. Measured (d = 0, t_end = 2000 to 8000):
k = 12, tau = 0.2: -3.450042 at dt = 1e-3 and -3.453017 at 5e-4, against -F' = -3.456
(-log(1 + dt F') / dt exactly; bias F' dt / 2 relative). k = 5, tau = 2:
-0.179522(56) at dt = 1e-3, against the discrete root -0.179551 and the leading root of
lambda^2 + F' lambda + k (1 - e^{-lambda tau}), -0.179662 (bias 6.2e-4 relative, halving
with dt).

Measured against scipy's Radau (rtol 1e-8, atol 1e-10, method of steps;
tests/radau_reference.py). Figures are max |m_y - m_y,Radau| over the run at
dt = 1e-3 / 5e-4 / 2.5e-4, with Euler at 1e-3 in brackets:
    defaults k = 10, tau = 10, t <= 100   1.93e-3 / 9.6e-4 / 4.8e-4     (Euler 7.8e-3)
    sliding k = 5, tau = 2, t <= 60        5.3e-4 / 2.6e-4 / 1.3e-4      (3.5e-4)
    sliding k = 12, tau = 0.5, t <= 30     1.37e-3 / 6.9e-4 / 3.4e-4     (1.36e-3)
    limit cycle k = 20, tau = 1, t <= 40   8.1e-2 / 4.0e-2 / 2.0e-2      (2.0e-1; phase drift)
    Fig. 7 a = 0.035, k = 12, tau = 1      rests on the branch: |m_y / 203.254992 - 1| < 2e-9
                                           for 1e-2 >= dt >= 5e-4. Runaway time (m_y = 100)
                                           off by 3.7e-4 / 1.5e-4 / 6.4e-5. (Euler: blow-up.)
    b = 9, tau = 0.2, k = 6 (delta = 0.1)  t >= 25: 1.4e-7; transient 0.11 / 0.062 / 0.053
                                           (Euler dt 1e-3: s_y = -2.05, wrong attractor
                                           m_y = 6e-5 against 0.9917; 5e-4 to 1e-4: blow-up)
    b = 10, tau = 0.5, k = 6               t >= 25: 6.3e-7; transient 0.29 / 0.27 / 0.24
                                           (Euler: blow-up at dt 1e-3 to 2.5e-4 and 5e-5;
                                           at 1e-4 it ends on a wrong state)
    b = 12, tau = 0.3, k = 20              t >= 25: 2e-12; transient 0.30 (0.12 at dt 1e-5)
s_y > 0 and s_x s_y - u^2 >= 0 held at every sample of all these runs. Radau's own minimum
of s_y was 7.7e-8 to 3e-5, and Euler broke both at every point.

Cost (a 2-core machine, the defaults, dt = 1e-3): 13.6 ns a step against Euler's 6.0
(2.3 times), and 15.3 against 8.0 (1.9 times) with lambda_max. Most of it is the latency of
the one division per step. We also tried putting d(6b)/ds_y into W. It cost 3 ns more per
step, changed the errors at the ordinary points by 10-25%, and put the Fig. 7 runaway's
time off by 3.8e-3, ten times more.
"""

from __future__ import annotations

from numba import njit

from core import chunk_state as cs
from core.model import JIT, damping, rhs, rhs_tangent
from core.recording import blown_up, keep, lowest, renormalise, sample

#: Largest -G h of a W-step. Where G < 0 the frozen covariance grows at up to -2G; the step
#: is split so that -G h <= 1/4, which keeps the step positive (module docstring).
GROWTH = 0.25
#: At most this many substeps per step. -G dt > MAX_SPLIT / 4 is a growth rate far beyond
#: any bounded state (a true divergence, e.g. a < 0), so the run ends as a blow-up.
MAX_SPLIT = 1 << 16


@njit(**JIT)
def w_solve(f_x, f_y, f_sx, f_sy, f_u, g, dt, k):
    """The increment dt W^{-1} f, with W = I - dt J_W and G = g held over the step:

        J_W:  (6a) m_y        (6c) 2u
              (6b) -g m_y     (6d) -2g s_y - 2k u
                              (6e) -g u - k s_x + s_y

    Write p1 = 1 + dt g, p2 = 1 + 2 dt g, p3 = p2 + 4 dt^2 k. The covariance block has
    determinant p1 p3. We eliminate 6c into 6e and 6d into 6e, then back-substitute 6d, 6c,
    6b, 6a. One reciprocal 1 / (p1 p2 p3) serves all the divisions.
    """
    p1 = 1.0 + dt * g
    p2 = 1.0 + 2.0 * dt * g
    p3 = p2 + 4.0 * dt * dt * k
    inv = 1.0 / (p1 * p2 * p3)
    dsx = dt * f_sx
    du = (dt * ((f_u - k * dsx) * p2 + dt * f_sy)) * (p2 * inv)  # / (p1 p3)
    dsy = (dt * f_sy - 2.0 * dt * k * du) * ((p1 * p3) * inv)    # / p2
    dsx += 2.0 * dt * du
    dy = dt * f_y * ((p2 * p3) * inv)                            # / p1
    dx = dt * (f_x + dy)                                         # m_y at n + 1
    return dx, dy, dsx, dsy, du


@njit(**JIT)
def stiff(coef, dt, n_delay, lyap, plan, hx, now, counts, ring, e_ring, win, trace, logs):
    """W-steps from step counts[N_AT] to plan[END]; return the steps done (plan[END], or
    n + 1 after a blow-up at step n).

    The contract, its arguments and the state arrays' layout: core.methods and
    core.chunk_state. The rings as core.euler.euler's (1, N): m_x over (t - tau, t].
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
    blown = False
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
        left, split = dt, 0
        while True:  # one W-step; substeps only where G < -GROWTH / dt (a runaway's growth)
            g = damping(m_y, s_y, a, q, f1)  # G, held over the (sub)step
            h = left if g * left >= -GROWTH else GROWTH / -g
            if lyap:
                f = rhs_tangent(m_y, s_y, u, e_x, e_y, e_sx, e_sy, e_u, e_x_tau, a, q, f1, k)
                w = w_solve(f[0], f[1], f[2], f[3], f[4], g, h, k)
                e_x += w[0]
                e_y += w[1]
                e_sx += w[2]
                e_sy += w[3]
                e_u += w[4]
            f = rhs(m_x, m_y, s_x, s_y, u, m_x_tau, a, q, f1, k, d)
            w = w_solve(f[0], f[1], f[2], f[3], f[4], g, h, k)
            m_x += w[0]
            m_y += w[1]
            s_x += w[2]
            s_y += w[3]
            u += w[4]
            if blown_up(m_y, s_y) or split == MAX_SPLIT:
                blown = True
                break
            if h >= left:
                break
            left -= h
            split += 1
        if blown:
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
