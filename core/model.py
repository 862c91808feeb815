"""Right-hand side of the mean-field system, eqs. 6a-6e, and its tangent-linear map.

The kernels in ``core.euler`` and ``core.rk4`` call these small functions; numba inlines
them, so they cost nothing over writing the formulas in the loop.

Coefficients are precomputed once per run (``coefficients``):
  F1 = F'(v) = 3 a v^2 - 2 b v + c     (the linear damping, eq. 10)
  q  = 3 a v - b                        (the quadratic coefficient)
so that eq. 6b reads  dm_y/dt = -F1 m_y - q m_y^2 - a m_y^3 - q s_y - 3 a m_y s_y
                                 + k (m_x,tau - m_x).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from core import jit_cache
from core.params import Params

# Every module with a kernel imports this one first, so the cache folder is set before
# any kernel is decorated.
jit_cache.configure()

#: numba options shared by every kernel. "contract" lets LLVM fuse a*b+c into one FMA,
#: which shortens the per-step dependency chain; we do not enable "nnan"/"fast", because
#: the blow-up test relies on NaN comparing false.
JIT = dict(cache=True, nogil=True, fastmath={"contract"})

def coefficients(p: Params) -> np.ndarray:
    """The constants the kernels need, as a float64 vector [a, q, F1, k, d, delta]."""
    return np.array([p.a, p.q, p.F1, p.k, p.d, p.delta], dtype=np.float64)


@njit(**JIT)
def dm_x(m_y: float) -> float:
    return m_y  # (6a)


@njit(**JIT)
def dm_y(m_x: float, m_y: float, s_y: float, m_x_tau: float, a: float, q: float, f1: float, k: float) -> float:
    # (6b), friction polynomial in Horner form
    return -m_y * (f1 + m_y * (q + a * m_y)) - s_y * (q + 3.0 * a * m_y) + k * (m_x_tau - m_x)


@njit(**JIT)
def damping(m_y: float, s_y: float, a: float, q: float, f1: float) -> float:
    # the bracket shared by (6d) and (6e): F'(v) + 2(3av - b) m_y + 3a (m_y^2 + s_y)
    return f1 + 2.0 * q * m_y + 3.0 * a * (m_y * m_y + s_y)


@njit(**JIT)
def ds_x(u: float) -> float:
    return 2.0 * u  # (6c)


@njit(**JIT)
def ds_y(s_y: float, u: float, g: float, k: float, d: float) -> float:
    return -2.0 * s_y * g - 2.0 * k * u + 2.0 * d  # (6d)


@njit(**JIT)
def du(s_x: float, s_y: float, u: float, g: float, k: float) -> float:
    return -u * g - k * s_x + s_y  # (6e)


@njit(**JIT)
def rhs(m_x, m_y, s_x, s_y, u, m_x_tau, a, q, f1, k, d):
    """The full vector field (6a-6e) at one state and one delayed m_x."""
    g = damping(m_y, s_y, a, q, f1)
    return (
        dm_x(m_y),
        dm_y(m_x, m_y, s_y, m_x_tau, a, q, f1, k),
        ds_x(u),
        ds_y(s_y, u, g, k, d),
        du(s_x, s_y, u, g, k),
    )


@njit(**JIT)
def rhs_tangent(m_y, s_y, u, e_x, e_y, e_sx, e_sy, e_u, e_x_tau, a, q, f1, k):
    """Jacobian of (6a-6e) at (m_y, s_y, u) applied to a tangent vector e.

    e_x_tau is the tangent of the delayed m_x. m_x itself enters only through
    k (m_x,tau - m_x), which is why a common shift of e_x and its history is neutral.
    """
    g = damping(m_y, s_y, a, q, f1)
    dg_dy = 2.0 * q + 6.0 * a * m_y
    e_g = dg_dy * e_y + 3.0 * a * e_sy
    return (
        e_y,
        -(f1 + m_y * (2.0 * q + 3.0 * a * m_y) + 3.0 * a * s_y) * e_y
        - (q + 3.0 * a * m_y) * e_sy
        + k * (e_x_tau - e_x),
        2.0 * e_u,
        -2.0 * (e_sy * g + s_y * e_g) - 2.0 * k * e_u,
        -(e_u * g + u * e_g) - k * e_sx + e_sy,
    )
