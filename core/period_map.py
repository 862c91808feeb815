"""The flow of the discretised delay equation from any history, and its tangent: the
building block of periodic orbits (core.orbit) and their continuation.

The simulation kernels start from eq. 19's constant history and keep only a ring buffer.
A periodic orbit needs the map from an arbitrary state to the state one period later,
and its derivative. The state of the RK4 scheme (core.rk4) at step n is the five
variables and (m_x, m_y) at the N = tau / dt steps before it: the Hermite interpolant
of the delayed m_x uses both. This kernel integrates the same RK4 stages with the same
Hermite midpoint, over one array that holds the whole trajectory from step -N, so the
delayed values are plain reads; with ``tangent`` it co-integrates the tangent-linear
stages (core.model.rhs_tangent) on a second array: the exact derivative of the
discrete map, as the lambda_max kernels use.
"""

from __future__ import annotations

from numba import njit

from core.model import JIT, rhs, rhs_tangent
from core.rk4 import hermite_mid


@njit(**JIT)
def flow(coef, dt, n_delay, traj, e_traj, tangent):
    """Fill traj[:, n_delay + 1:] with RK4 steps from the state in traj[:, :n_delay + 1].

    traj has rows m_x, m_y, s_x, s_y, u and one column per step, column n_delay being
    step 0; before step 0 only m_x and m_y are read (the delayed values). e_traj holds the
    tangent in the same layout and is filled when ``tangent``. Returns the number of
    columns filled (fewer than asked once |m_y| or |s_y| leaves the finite range).
    """
    a, q, f1, k, d = coef[0], coef[1], coef[2], coef[3], coef[4]
    h = 0.5 * dt
    w = dt / 6.0
    n_cols = traj.shape[1]
    for j in range(n_delay, n_cols - 1):
        o = j - n_delay  # the column of t - tau
        x0, x1 = traj[0, o], traj[0, o + 1]
        xh = hermite_mid(x0, x1, traj[1, o], traj[1, o + 1], dt)
        m_x, m_y, s_x, s_y, u = traj[0, j], traj[1, j], traj[2, j], traj[3, j], traj[4, j]
        k1 = rhs(m_x, m_y, s_x, s_y, u, x0, a, q, f1, k, d)
        x2, y2, sx2, sy2, u2 = m_x + h * k1[0], m_y + h * k1[1], s_x + h * k1[2], s_y + h * k1[3], u + h * k1[4]
        k2 = rhs(x2, y2, sx2, sy2, u2, xh, a, q, f1, k, d)
        x3, y3, sx3, sy3, u3 = m_x + h * k2[0], m_y + h * k2[1], s_x + h * k2[2], s_y + h * k2[3], u + h * k2[4]
        k3 = rhs(x3, y3, sx3, sy3, u3, xh, a, q, f1, k, d)
        x4, y4, sx4, sy4, u4 = m_x + dt * k3[0], m_y + dt * k3[1], s_x + dt * k3[2], s_y + dt * k3[3], u + dt * k3[4]
        k4 = rhs(x4, y4, sx4, sy4, u4, x1, a, q, f1, k, d)
        for r in range(5):
            traj[r, j + 1] = traj[r, j] + w * (k1[r] + 2.0 * (k2[r] + k3[r]) + k4[r])
        if not (abs(traj[1, j + 1]) < 1e6 and abs(traj[3, j + 1]) < 1e6):
            return j + 2
        if tangent:
            e0, e1 = e_traj[0, o], e_traj[0, o + 1]
            eh = hermite_mid(e0, e1, e_traj[1, o], e_traj[1, o + 1], dt)
            e = (e_traj[0, j], e_traj[1, j], e_traj[2, j], e_traj[3, j], e_traj[4, j])
            t1 = rhs_tangent(m_y, s_y, u, e[0], e[1], e[2], e[3], e[4], e0, a, q, f1, k)
            g = (e[0] + h * t1[0], e[1] + h * t1[1], e[2] + h * t1[2], e[3] + h * t1[3], e[4] + h * t1[4])
            t2 = rhs_tangent(y2, sy2, u2, g[0], g[1], g[2], g[3], g[4], eh, a, q, f1, k)
            g = (e[0] + h * t2[0], e[1] + h * t2[1], e[2] + h * t2[2], e[3] + h * t2[3], e[4] + h * t2[4])
            t3 = rhs_tangent(y3, sy3, u3, g[0], g[1], g[2], g[3], g[4], eh, a, q, f1, k)
            g = (e[0] + dt * t3[0], e[1] + dt * t3[1], e[2] + dt * t3[2], e[3] + dt * t3[3], e[4] + dt * t3[4])
            t4 = rhs_tangent(y4, sy4, u4, g[0], g[1], g[2], g[3], g[4], e1, a, q, f1, k)
            for r in range(5):
                e_traj[r, j + 1] = e[r] + w * (t1[r] + 2.0 * (t2[r] + t3[r]) + t4[r])
    return n_cols
