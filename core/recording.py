"""What a run keeps while it integrates, shared by the Euler and RK4 kernels.

A run to t_end = 1e5 at dt = 1e-3 takes 1e8 steps, so nothing keeps the whole trajectory.
Two samplers write the five variables into preallocated (5, n) arrays:
  - the analysis window: every ``stride`` steps from ``start`` on (the last ``window``
    time units, as the paper's [99000, 100000]);
  - the trace: every ``stride`` steps from t = 0, a few thousand points for plots.
The tangent-linear renormalisation (for lambda_max) also lives here, because both
schemes share it.
"""

from __future__ import annotations

import math

from numba import njit

from core.model import JIT

#: A run is "unstable" once |m_y| or |s_y| exceeds this bound, or a value is not finite.
#: Bounded attractors we measured stay far below it: |m_y| <= ~2 on the default planes,
#: and the largest bounded excursions at low a (a = 0.03-0.04, Fig. 7) reach |m_y| ~ 1e2.
#: Past 1e6 the cubic terms grow faster than any step can resolve and the run diverges
#: to inf within a few steps, so the bound only shortens a run that is already lost.
BLOWUP_BOUND = 1e6


@njit(**JIT)
def sample(n, next_n, i, stride, out, m_x, m_y, s_x, s_y, u):
    """Store the state in column i of ``out`` if step n is due; return (next_n, i)."""
    if n == next_n and i < out.shape[1]:
        out[0, i] = m_x
        out[1, i] = m_y
        out[2, i] = s_x
        out[3, i] = s_y
        out[4, i] = u
        return next_n + stride, i + 1
    return next_n, i


@njit(**JIT)
def blown_up(m_y: float, s_y: float) -> bool:
    # written so that NaN (which compares false) counts as a blow-up
    return not (abs(m_y) < BLOWUP_BOUND and abs(s_y) < BLOWUP_BOUND)


@njit(**JIT)
def renormalise(e_x, e_y, e_sx, e_sy, e_u, history, dt):
    """Project out the neutral translation mode, measure the tangent, scale it to 1.

    The discrete state is the five variables plus the delay buffer(s) ``history``
    (row 0: tangent m_x over the last tau; row 1, for RK4: tangent m_y). Shifting m_x
    and its whole history by a constant changes nothing (only m_x,tau - m_x enters
    eq. 6b), so we subtract the current e_x from row 0 and from e_x, and use the norm
        |e|^2 = e_y^2 + e_sx^2 + e_sy^2 + e_u^2 + dt * sum_rows sum_j h_j^2.
    Returns log|e| and the scaled five-vector.
    """
    acc = 0.0
    for j in range(history.shape[1]):
        history[0, j] -= e_x
        acc += history[0, j] * history[0, j]
    for r in range(1, history.shape[0]):
        for j in range(history.shape[1]):
            acc += history[r, j] * history[r, j]
    norm = math.sqrt(e_y * e_y + e_sx * e_sx + e_sy * e_sy + e_u * e_u + dt * acc)
    inv = 1.0 / norm
    for r in range(history.shape[0]):
        for j in range(history.shape[1]):
            history[r, j] *= inv
    return math.log(norm), 0.0, e_y * inv, e_sx * inv, e_sy * inv, e_u * inv
