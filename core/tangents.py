"""Kernels for the Lyapunov spectrum: a run's own scheme with N tangents (core.spectrum).

Each kernel integrates eqs. 6a-6e exactly as core.euler or core.rk4 does (their step
functions, from the same history: the same discrete map) and co-iterates N tangent vectors
of that map (the same tangent steps), each with its own delay
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

from core.euler import euler_step, euler_tangent_step
from core.model import JIT
from core.recording import blown_up
from core.rk4 import hermite_mid, rk4_step, rk4_tangent_step


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
    Returns n_steps, or minus the steps done at a blow-up (the step that blew up
    counted: at the last step too, where a count alone would not tell)."""
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
            e[i, 0], e[i, 1], e[i, 2], e[i, 3], e[i, 4] = euler_tangent_step(
                m_y, s_y, u, e[i, 0], e[i, 1], e[i, 2], e[i, 3], e[i, 4], e_x_tau, dt, a, q, f1, k)
        if n_delay > 0:
            pos += 1
            if pos == n_delay:
                pos = 0
        m_x, m_y, s_x, s_y, u = euler_step(m_x, m_y, s_x, s_y, u, m_x_tau, dt, a, q, f1, k, d)
        if blown_up(m_y, s_y):
            return -(n + 1)  # negative: blew up, even at the last step
        if n + 1 == next_r:
            orthonormalise(e, h, h.shape[2], dt, logs, i_r)
            i_r += 1
            next_r += renorm_steps
    return n_steps


@njit(**JIT)
def rk4_tangents(coef, dt, n_delay, n_steps, renorm_steps, init, hx, e, h, logs):
    """core.rk4.rk4's steps with the N = e.shape[0] tangents e (N, 5) and their rings h
    (N, 2, n_delay + 1) of tangent (m_x, m_y), laid out as core.rk4's: slot j >= 1 holds
    step j - 1 - N at the start, which the tangents read through the same Hermite cubic
    (the state reads hx before t = 0). logs as euler_tangents."""
    a, q, f1, k, d = coef[0], coef[1], coef[2], coef[3], coef[4]
    m_x, m_y, s_x, s_y, u = init[0], init[1], init[2], init[3], init[4]  # (19)
    size = n_delay + 1
    hist = np.empty((2, size))         # rows: m_x, m_y
    nv = e.shape[0]
    no_delay = n_delay == 0
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
            xh = hermite_mid(x0, x1, hist[1, old], hist[1, nxt], dt)
        x_new, y_new, sx_new, sy_new, u_new, stages = rk4_step(m_x, m_y, s_x, s_y, u, x0, xh, x1,
                                                              no_delay, dt, a, q, f1, k, d)
        for i in range(nv):
            ex0 = exh = ex1 = 0.0
            if not no_delay:
                ex0, ex1 = h[i, 0, old], h[i, 0, nxt]
                exh = hermite_mid(ex0, ex1, h[i, 1, old], h[i, 1, nxt], dt)
            e[i, 0], e[i, 1], e[i, 2], e[i, 3], e[i, 4] = rk4_tangent_step(
                m_y, s_y, u, stages, e[i, 0], e[i, 1], e[i, 2], e[i, 3], e[i, 4], ex0, exh, ex1,
                no_delay, dt, a, q, f1, k)
        m_x, m_y, s_x, s_y, u = x_new, y_new, sx_new, sy_new, u_new
        if blown_up(m_y, s_y):
            return -(n + 1)  # negative: blew up, even at the last step
        if n + 1 == next_r:
            # the slot at pos (step n - N) is stale: make it vanish from the inner product
            for i in range(nv):
                h[i, 0, pos] = e[i, 0]
                h[i, 1, pos] = 0.0
            orthonormalise(e, h, size, dt, logs, i_r)
            i_r += 1
            next_r += renorm_steps
    return n_steps
