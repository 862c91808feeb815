"""What a run keeps while it integrates, shared by the Euler and RK4 kernels.

A run to t_end = 1e5 at dt = 1e-3 takes 1e8 steps, so nothing keeps the whole trajectory.
Two samplers write the five variables into preallocated (5, n) arrays:
  - the analysis window: every ``stride`` steps over the last ``window`` time units (as
    the paper's [99000, 100000]), and as long a window ending at the middle of the run
    (to tell a settled attractor from a slow transient, core.classify);
  - the trace: every ``stride`` steps from t = 0, a few thousand points for plots.
The tangent-linear renormalisation (for lambda_max) also lives here, because both
schemes share it, and so do the running minima of the covariance over every step
(lowest: whether the run stayed realisable, core.closure) and the write-back of a
kernel's state where the next chunk continues from it (keep, core.chunk_state).
"""

from __future__ import annotations

import math

from numba import njit

from core import chunk_state as cs
from core.closure import REALISABLE_TOL
from core.model import JIT

#: A run is "unstable" once |m_y| or |s_y| exceeds this bound, or a value is not finite.
#: Bounded attractors stay far below it: peak-to-peak m_y reached ~10 at most in our
#: scans (b up to 24, tau up to 20, k = 6 and 12). At low a (Fig. 7, a = 0.035) the
#: exact solution jumps to a fast-sliding branch at m_y ~ 205 (checked with a stiff
#: Radau solver), where the s_y equation decays at a rate ~3000:
#: beyond the stability limit of explicit Euler (2/dt = 2000) and of RK4 at dt = 0.01,
#: so s_y then diverges within a few steps and crosses the bound. The bound only ends a
#: run the integrator has already lost; the paper calls this "numerical infinity".
BLOWUP_BOUND = 1e6


@njit(**JIT)
def sample(n, next_n, i, stride, jump, resume, out, m_x, m_y, s_x, s_y, u):
    """Store the state in column i of ``out`` if step n is due; return (next_n, i).

    Samples are due every ``stride`` steps, except that after column ``jump - 1`` the
    next one is due at step ``resume``: the analysis window is two windows, the middle
    of the run and its end (core.solve.make_grid), in one array. jump = -1: no jump.
    """
    if n == next_n and i < out.shape[1]:
        out[0, i] = m_x
        out[1, i] = m_y
        out[2, i] = s_x
        out[3, i] = s_y
        out[4, i] = u
        i += 1
        return (resume if i == jump else next_n + stride), i
    return next_n, i


@njit(**JIT)
def keep(now, counts, m_x, m_y, s_x, s_y, u, e_x, e_y, e_sx, e_sy, e_u, lo_x, lo_y, lo_d,
         n, pos, next_w, i_w, next_t, i_t, next_r, i_r, first):
    """Write a kernel's state back into ``now`` and ``counts`` (layout: core.chunk_state),
    where a later call continues from it: at step n, ring position pos."""
    now[cs.M_X], now[cs.M_Y], now[cs.S_X], now[cs.S_Y], now[cs.U] = m_x, m_y, s_x, s_y, u
    now[cs.E_X], now[cs.E_Y], now[cs.E_SX], now[cs.E_SY], now[cs.E_U] = e_x, e_y, e_sx, e_sy, e_u
    now[cs.LO_X], now[cs.LO_Y], now[cs.LO_D] = lo_x, lo_y, lo_d
    counts[cs.N_AT], counts[cs.POS], counts[cs.FIRST] = n, pos, first
    counts[cs.NEXT_W], counts[cs.I_W], counts[cs.NEXT_T], counts[cs.I_T] = next_w, i_w, next_t, i_t
    counts[cs.NEXT_R], counts[cs.I_R] = next_r, i_r


@njit(**JIT)
def lowest(lo_x, lo_y, lo_d, first, n, s_x, s_y, u):
    """The running minima of s_x, s_y and s_x s_y - u^2 with the state of step n, and the
    first step at which one fell below -REALISABLE_TOL (-1: none yet; core.closure).

    Kept in the kernels' registers, step by step: the comparisons sit beside the step's
    dependency chain, not on it, and the branch is almost never taken. A NaN (blow-up)
    compares false and leaves the minima alone."""
    det = s_x * s_y - u * u
    if s_x < lo_x:
        lo_x = s_x
    if s_y < lo_y:
        lo_y = s_y
    if det < lo_d:
        lo_d = det
    if first < 0 and (lo_x < -REALISABLE_TOL or lo_y < -REALISABLE_TOL or lo_d < -REALISABLE_TOL):
        first = n
    return lo_x, lo_y, lo_d, first


@njit(**JIT)
def blown_up(m_y: float, s_y: float) -> bool:
    # written so that NaN (which compares false) counts as a blow-up
    return not (abs(m_y) < BLOWUP_BOUND and abs(s_y) < BLOWUP_BOUND)


@njit(**JIT)
def renormalise(e_x, e_y, e_sx, e_sy, e_u, history, n, dt):
    """Project out the neutral translation mode, measure the tangent, scale it to 1.

    The discrete state is the five variables plus the delay buffer(s) ``history[:, :n]``
    (row 0: tangent m_x over the last tau; row 1, for RK4: tangent m_y; the batch's
    buffers are wider than n, and a C-contiguous row is what lets LLVM vectorise the
    loops over it). Shifting m_x and its whole history by a constant changes nothing
    (only m_x,tau - m_x enters eq. 6b), so we subtract the current e_x from row 0 and
    from e_x, and use the norm
        |e|^2 = e_y^2 + e_sx^2 + e_sy^2 + e_u^2 + dt * sum_rows sum_j h_j^2.
    Returns log|e| and the scaled five-vector.

    The history runs over tau/dt values and is renormalised every tau, so this costs
    about one history value per step: summed into four partial sums, not one, so that
    the additions do not wait for each other (one sum cost ~1.3 ns per step).
    """
    acc = _sum_of_squares(history[0], n, e_x)
    for r in range(1, history.shape[0]):
        acc += _sum_of_squares(history[r], n, 0.0)
    norm = math.sqrt(e_y * e_y + e_sx * e_sx + e_sy * e_sy + e_u * e_u + dt * acc)
    inv = 1.0 / norm
    row = history[0]
    for j in range(n):
        row[j] = (row[j] - e_x) * inv
    for r in range(1, history.shape[0]):
        row = history[r]
        for j in range(n):
            row[j] *= inv
    return math.log(norm), 0.0, e_y * inv, e_sx * inv, e_sy * inv, e_u * inv


@njit(**JIT)
def _sum_of_squares(row, n, shift):
    """sum_{j < n} (row[j] - shift)^2, in four interleaved partial sums."""
    a0 = a1 = a2 = a3 = 0.0
    n4 = n - n % 4
    for j in range(0, n4, 4):
        h0, h1, h2, h3 = row[j] - shift, row[j + 1] - shift, row[j + 2] - shift, row[j + 3] - shift
        a0 += h0 * h0
        a1 += h1 * h1
        a2 += h2 * h2
        a3 += h3 * h3
    for j in range(n4, n):
        h = row[j] - shift
        a0 += h * h
    return (a0 + a1) + (a2 + a3)
