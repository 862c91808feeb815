"""Kernels for the Lyapunov spectrum: a run's own scheme with N tangents (core.spectrum).

Each kernel integrates eqs. 6a-6e exactly as core.euler or core.rk4 does (the same steps
from the same history, so the same trajectory up to how LLVM fuses multiply-adds in each
kernel) and co-iterates N tangent vectors of that discrete map, each with its own delay
ring, re-orthonormalising them every ``renorm_steps`` steps (``orthonormalise``). The main
kernels stay as they are: a run with --spectrum pays for this second pass, and a run
without it pays nothing.

A tangent is its five-vector e[i] = (e_x, e_y, e_sx, e_sy, e_u) and its history
h[i] (rows: tangent m_x, and for RK4 tangent m_y, over the delay). The initial tangents
come from the caller (random, so that N of them are independent: the five variables
alone span only four directions besides the shift); their history before t = 0 is read
as a perturbation of the initial history, so every direction is excited from the start.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from core.model import JIT, rhs, rhs_tangent
from core.recording import blown_up


@njit(**JIT)
def _dot(e, h, i, j, n, dt):
    """<tangent i, tangent j>: e_y, e_sx, e_sy, e_u and dt times the history rows, over
    n slots (the inner product whose norm core.recording.renormalise uses). Four partial
    sums, as core.recording._sum_of_squares, so that the additions do not wait for each
    other."""
    a0 = a1 = a2 = a3 = 0.0
    n4 = n - n % 4
    for r in range(h.shape[1]):
        x, y = h[i, r], h[j, r]
        for s in range(0, n4, 4):
            a0 += x[s] * y[s]
            a1 += x[s + 1] * y[s + 1]
            a2 += x[s + 2] * y[s + 2]
            a3 += x[s + 3] * y[s + 3]
        for s in range(n4, n):
            a0 += x[s] * y[s]
    acc = (a0 + a1) + (a2 + a3)
    return e[i, 1] * e[j, 1] + e[i, 2] * e[j, 2] + e[i, 3] * e[j, 3] + e[i, 4] * e[j, 4] + dt * acc


@njit(**JIT)
def _project_out(e, h, i, n, dt):
    """Tangent i minus its components along tangents 0..i-1 (orthonormal): one pass of
    modified Gram-Schmidt."""
    for j in range(i):
        c = _dot(e, h, i, j, n, dt)
        for m in range(5):
            e[i, m] -= c * e[j, m]
        for r in range(h.shape[1]):
            x, y = h[i, r], h[j, r]
            for s in range(n):
                x[s] -= c * y[s]


@njit(**JIT)
def orthonormalise(e, h, n, dt, logs, row):
    """Quotient out the m_x shift, then Gram-Schmidt: logs[row, i] = log of tangent i's
    length after the ones before it are projected out (the R of a QR, diagonal).

    The shift (e_x and the whole tangent m_x history moved by one constant) is exactly
    neutral (only m_x,tau - m_x enters eq. 6b): each tangent's representative with e_x = 0
    is taken, as for lambda_max. A second pass of the projection only where the first
    cancelled more than half the length (Kahan's "twice is enough"), where one pass loses
    orthogonality: a second pass everywhere cost 1.6 times as much at N = 8 (Euler, tau =
    10) and changed none of the exponents we checked in their printed digits."""
    nv = e.shape[0]
    for i in range(nv):
        shift = e[i, 0]
        for s in range(n):
            h[i, 0, s] -= shift
        e[i, 0] = 0.0
    for i in range(nv):
        before = _dot(e, h, i, i, n, dt)
        _project_out(e, h, i, n, dt)
        after = _dot(e, h, i, i, n, dt)
        if after < 0.25 * before:
            _project_out(e, h, i, n, dt)
            after = _dot(e, h, i, i, n, dt)
        norm = math.sqrt(after)
        logs[row, i] = math.log(norm)
        inv = 1.0 / norm
        for m in range(5):
            e[i, m] *= inv
        for r in range(h.shape[1]):
            for s in range(n):
                h[i, r, s] *= inv


@njit(**JIT)
def euler_tangents(coef, dt, n_delay, n_steps, renorm_steps, init, hx, e, h, logs):
    """core.euler.euler's steps with the N = e.shape[0] tangents e (N, 5) and their m_x
    rings h (N, 1, n_delay); logs (n_steps // renorm_steps, N) receives the log-growths.
    Returns the steps done (< n_steps on blow-up)."""
    a, q, f1, k, d = coef[0], coef[1], coef[2], coef[3], coef[4]
    m_x, m_y, s_x, s_y, u = init[0], init[1], init[2], init[3], init[4]  # (19)
    hist = hx[0:2 * n_delay:2].copy()  # m_x(-tau + j dt): the history
    nv = e.shape[0]
    pos = 0
    next_r, i_r = renorm_steps, 0
    for n in range(n_steps):
        if n_delay > 0:
            m_x_tau = hist[pos]
            hist[pos] = m_x
        else:
            m_x_tau = m_x
        for i in range(nv):
            if n_delay > 0:
                e_x_tau = h[i, 0, pos]
                h[i, 0, pos] = e[i, 0]
            else:
                e_x_tau = e[i, 0]
            f = rhs_tangent(m_y, s_y, u, e[i, 0], e[i, 1], e[i, 2], e[i, 3], e[i, 4], e_x_tau,
                            a, q, f1, k)
            for m in range(5):
                e[i, m] += dt * f[m]
        if n_delay > 0:
            pos += 1
            if pos == n_delay:
                pos = 0
        f = rhs(m_x, m_y, s_x, s_y, u, m_x_tau, a, q, f1, k, d)
        m_x += dt * f[0]
        m_y += dt * f[1]
        s_x += dt * f[2]
        s_y += dt * f[3]
        u += dt * f[4]
        if blown_up(m_y, s_y):
            return n + 1
        if n + 1 == next_r:
            orthonormalise(e, h, h.shape[2], dt, logs, i_r)
            i_r += 1
            next_r += renorm_steps
    return n_steps


@njit(**JIT)
def _rk4_tangent(e, i, exs, ys, sys, us, y2, sy2, u2, y3, sy3, u3, y4, sy4, u4, a, q, f1, k, dt,
                 no_delay):
    """One RK4 step of tangent i: core.rk4's stages differentiated, exs = (e_x,tau at the
    step's start, middle and end)."""
    h2 = 0.5 * dt
    x, y, sx, sy, uu = e[i, 0], e[i, 1], e[i, 2], e[i, 3], e[i, 4]
    t1 = rhs_tangent(ys, sys, us, x, y, sx, sy, uu, x if no_delay else exs[0], a, q, f1, k)
    g = (x + h2 * t1[0], y + h2 * t1[1], sx + h2 * t1[2], sy + h2 * t1[3], uu + h2 * t1[4])
    t2 = rhs_tangent(y2, sy2, u2, g[0], g[1], g[2], g[3], g[4], g[0] if no_delay else exs[1],
                     a, q, f1, k)
    g = (x + h2 * t2[0], y + h2 * t2[1], sx + h2 * t2[2], sy + h2 * t2[3], uu + h2 * t2[4])
    t3 = rhs_tangent(y3, sy3, u3, g[0], g[1], g[2], g[3], g[4], g[0] if no_delay else exs[1],
                     a, q, f1, k)
    g = (x + dt * t3[0], y + dt * t3[1], sx + dt * t3[2], sy + dt * t3[3], uu + dt * t3[4])
    t4 = rhs_tangent(y4, sy4, u4, g[0], g[1], g[2], g[3], g[4], g[0] if no_delay else exs[2],
                     a, q, f1, k)
    w = dt / 6.0
    for m in range(5):
        e[i, m] += w * (t1[m] + 2.0 * (t2[m] + t3[m]) + t4[m])


@njit(**JIT)
def rk4_tangents(coef, dt, n_delay, n_steps, renorm_steps, init, hx, e, h, logs):
    """core.rk4.rk4's steps with the N = e.shape[0] tangents e (N, 5) and their rings h
    (N, 2, n_delay + 1) of tangent (m_x, m_y), laid out as core.rk4's: slot j >= 1 holds
    step j - 1 - N at the start, which the tangents read through the same Hermite cubic
    (the state reads hx before t = 0). logs as euler_tangents."""
    a, q, f1, k, d = coef[0], coef[1], coef[2], coef[3], coef[4]
    hh = 0.5 * dt
    m_x, m_y, s_x, s_y, u = init[0], init[1], init[2], init[3], init[4]  # (19)
    size = n_delay + 1
    hist = np.empty((2, size))         # rows: m_x, m_y
    nv = e.shape[0]
    no_delay = n_delay == 0
    exs = np.zeros(3)                  # e_x,tau at the stage times, per tangent
    pos = 0
    next_r, i_r = renorm_steps, 0
    for n in range(n_steps):
        hist[0, pos] = m_x
        hist[1, pos] = m_y
        for i in range(nv):
            h[i, 0, pos] = e[i, 0]
            h[i, 1, pos] = e[i, 1]
        old = pos + 1 if pos + 1 < size else 0   # step n - N
        nxt = old + 1 if old + 1 < size else 0   # step n - N + 1
        pos = old
        if no_delay:
            x0 = xh = x1 = 0.0
        elif n < n_delay:
            x0, xh, x1 = hx[2 * n], hx[2 * n + 1], hx[2 * n + 2]
        else:
            x0, x1 = hist[0, old], hist[0, nxt]
            xh = 0.5 * (x0 + x1) + 0.125 * dt * (hist[1, old] - hist[1, nxt])
        xs, ys, sxs, sys, us = m_x, m_y, s_x, s_y, u
        k1 = rhs(xs, ys, sxs, sys, us, xs if no_delay else x0, a, q, f1, k, d)
        x2, y2, sx2, sy2, u2 = m_x + hh * k1[0], m_y + hh * k1[1], s_x + hh * k1[2], s_y + hh * k1[3], u + hh * k1[4]
        k2 = rhs(x2, y2, sx2, sy2, u2, x2 if no_delay else xh, a, q, f1, k, d)
        x3, y3, sx3, sy3, u3 = m_x + hh * k2[0], m_y + hh * k2[1], s_x + hh * k2[2], s_y + hh * k2[3], u + hh * k2[4]
        k3 = rhs(x3, y3, sx3, sy3, u3, x3 if no_delay else xh, a, q, f1, k, d)
        x4, y4, sx4, sy4, u4 = m_x + dt * k3[0], m_y + dt * k3[1], s_x + dt * k3[2], s_y + dt * k3[3], u + dt * k3[4]
        k4 = rhs(x4, y4, sx4, sy4, u4, x4 if no_delay else x1, a, q, f1, k, d)
        for i in range(nv):
            if not no_delay:
                exs[0], exs[2] = h[i, 0, old], h[i, 0, nxt]
                exs[1] = 0.5 * (exs[0] + exs[2]) + 0.125 * dt * (h[i, 1, old] - h[i, 1, nxt])
            _rk4_tangent(e, i, exs, ys, sys, us, y2, sy2, u2, y3, sy3, u3, y4, sy4, u4,
                         a, q, f1, k, dt, no_delay)
        w = dt / 6.0
        m_x += w * (k1[0] + 2.0 * (k2[0] + k3[0]) + k4[0])
        m_y += w * (k1[1] + 2.0 * (k2[1] + k3[1]) + k4[1])
        s_x += w * (k1[2] + 2.0 * (k2[2] + k3[2]) + k4[2])
        s_y += w * (k1[3] + 2.0 * (k2[3] + k3[3]) + k4[3])
        u += w * (k1[4] + 2.0 * (k2[4] + k3[4]) + k4[4])
        if blown_up(m_y, s_y):
            return n + 1
        if n + 1 == next_r:
            # the slot at pos (step n - N) is stale: make it vanish from the inner product
            for i in range(nv):
                h[i, 0, pos] = e[i, 0]
                h[i, 1, pos] = 0.0
            orthonormalise(e, h, size, dt, logs, i_r)
            i_r += 1
            next_r += renorm_steps
    return n_steps
