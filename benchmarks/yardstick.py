"""The yardstick: minimal structure-of-arrays kernels of each shape core.batch computes.

The batched kernels' targets are set as ratios to a minimal kernel of the same shape
measured in the same run (benchmarks/bench_kernels.py): Euler and Euler + lambda_max
within 1.25x. These kernels do only what every step must: the equations (core.model, the
same functions the engine inlines), the delay ring of lanes sharing tau (delay-major, one
contiguous row per step, unsigned indices), and for lambda_max the tangent and its
renormalisation every tau. No samples, no blow-up test, no events, no lanes leaving:
what core.batch adds on top of them is what the ratio measures.

They are written with what made LLVM vectorise core.batch's loops (its docstrings say
how each was measured): rows of one flat state at a compile-time stride, every store
spelled out, the tangent in a loop of its own, and for RK4 + lambda_max the delayed values
and the stages kept in rows before the loops that use them. A yardstick slower than the
engine would flatter it; benchmarks/bench_kernels.py prints both.

Each kernel takes coef (lanes, 6) as core.model.coefficients gives it, the common step dt
and delay n_delay = tau / dt (> 0), and integrates n_steps from eq. 19's constant state and
history; it returns the state (5, lanes) and, with lambda_max, the sum of the logs.
"""

from __future__ import annotations

import numpy as np
from numba import njit, uint64

from core.model import rhs, rhs_tangent
from core.rk4 import hermite_mid

OPTS = dict(cache=True, nogil=True, fastmath={"contract"}, error_model="numpy")
S = 64  # compile-time row stride: at most 64 lanes
(MX, MY, SX, SY, U, EX, EY, ESX, ESY, EU, CA, CQ, CF1, CK, CD,
 X0, XH, X1, E0, EH, E1) = range(21)


@njit(**OPTS)
def _buffers(n_ring, n_e_ring, n_sc):
    """st (21 rows), the ring, the tangent's ring and the stages in one allocation, each
    after st starting half a row (256 bytes) past a multiple of a row (512 bytes) from st:
    the layout core.batch.skewed_buffers gives the engine against 4K aliasing, so that the
    yardstick does not lose by its allocations' offsets either."""
    starts = np.empty(3, dtype=np.int64)
    end = 21 * S
    for i, n in enumerate((n_ring, n_e_ring, n_sc)):
        starts[i] = end + (S // 2 - end) % S
        end = starts[i] + n
    buf = np.zeros(end)
    return (buf[:21 * S], buf[starts[0]:starts[0] + n_ring],
            buf[starts[1]:starts[1] + n_e_ring], buf[starts[2]:starts[2] + n_sc])


@njit(**OPTS)
def _start(coef, st):
    for j in range(coef.shape[0]):
        for r in range(5):
            st[r * S + j] = coef[j, 5]
            st[(CA + r) * S + j] = coef[j, r]
        for r in range(EY, EU + 1):
            st[r * S + j] = 1.0


@njit(**OPTS)
def _renormalise(n_l, st, e_ring, rows, parity, dt):
    acc = np.zeros(n_l)
    for r in range(rows):
        s = 1.0 if r % parity == 0 else 0.0
        for j in range(n_l):
            h = e_ring[r * n_l + j] - s * st[EX * S + j]
            acc[j] += h * h
    total = 0.0
    for j in range(n_l):
        norm = np.sqrt(st[EY * S + j] ** 2 + st[ESX * S + j] ** 2 + st[ESY * S + j] ** 2
                       + st[EU * S + j] ** 2 + dt * acc[j])
        total += np.log(norm)
        acc[j] = 1.0 / norm
    for r in range(rows):
        s = 1.0 if r % parity == 0 else 0.0
        for j in range(n_l):
            e_ring[r * n_l + j] = (e_ring[r * n_l + j] - s * st[EX * S + j]) * acc[j]
    for j in range(n_l):
        st[EX * S + j] = 0.0
        for r in range(EY, EU + 1):
            st[r * S + j] *= acc[j]
    return total


@njit(**OPTS)
def euler(coef, dt, n_delay, n_steps, lyap):
    n_l = coef.shape[0]
    st, ring, e_ring, _ = _buffers(n_delay * n_l, n_delay * n_l, 0)
    _start(coef, st)
    ring[:] = coef[0, 5]
    pos, logs = 0, 0.0
    for _ in range(n_steps):
        row = uint64(pos * n_l)
        if lyap:
            for j in range(n_l):
                e_x = st[EX * S + j]
                e_tau = e_ring[row + uint64(j)]
                e_ring[row + uint64(j)] = e_x
                f = rhs_tangent(st[MY * S + j], st[SY * S + j], st[U * S + j], e_x, st[EY * S + j],
                                st[ESX * S + j], st[ESY * S + j], st[EU * S + j], e_tau,
                                st[CA * S + j], st[CQ * S + j], st[CF1 * S + j], st[CK * S + j])
                st[EX * S + j] = e_x + dt * f[0]
                st[EY * S + j] += dt * f[1]
                st[ESX * S + j] += dt * f[2]
                st[ESY * S + j] += dt * f[3]
                st[EU * S + j] += dt * f[4]
        for j in range(n_l):
            m_x = st[MX * S + j]
            m_x_tau = ring[row + uint64(j)]
            ring[row + uint64(j)] = m_x
            f = rhs(m_x, st[MY * S + j], st[SX * S + j], st[SY * S + j], st[U * S + j], m_x_tau,
                    st[CA * S + j], st[CQ * S + j], st[CF1 * S + j], st[CK * S + j], st[CD * S + j])
            st[MX * S + j] = m_x + dt * f[0]
            st[MY * S + j] += dt * f[1]
            st[SX * S + j] += dt * f[2]
            st[SY * S + j] += dt * f[3]
            st[U * S + j] += dt * f[4]
        pos += 1
        if pos == n_delay:
            pos = 0
            if lyap:  # renormalise every tau
                logs += _renormalise(n_l, st, e_ring, n_delay, 1, dt)
    return st[:5 * S].reshape(5, S)[:, :n_l].copy(), logs


@njit(**OPTS)
def _y(a, j, r):   # five rows from row r (or three: the stages' (m_y, s_y, u) need [:3])
    return a[r * S + j], a[(r + 1) * S + j], a[(r + 2) * S + j], a[(r + 3) * S + j], a[(r + 4) * S + j]


@njit(**OPTS)
def _y3(a, j, r):
    return a[r * S + j], a[(r + 1) * S + j], a[(r + 2) * S + j]


@njit(**OPTS)
def _put(a, j, r, y):
    a[r * S + j], a[(r + 1) * S + j], a[(r + 2) * S + j], a[(r + 3) * S + j], a[(r + 4) * S + j] = y


@njit(**OPTS)
def _f(y, x_tau, c):
    return rhs(y[0], y[1], y[2], y[3], y[4], x_tau, c[0], c[1], c[2], c[3], c[4])


@njit(**OPTS)
def _t(y3, e, e_tau, c):
    return rhs_tangent(y3[0], y3[1], y3[2], e[0], e[1], e[2], e[3], e[4], e_tau, c[0], c[1], c[2], c[3])


@njit(**OPTS)
def _add(y, c, k):
    return y[0] + c * k[0], y[1] + c * k[1], y[2] + c * k[2], y[3] + c * k[3], y[4] + c * k[4]


@njit(**OPTS)
def _sum(y, w, k1, k2, k3, k4):
    return (y[0] + w * (k1[0] + 2.0 * (k2[0] + k3[0]) + k4[0]), y[1] + w * (k1[1] + 2.0 * (k2[1] + k3[1]) + k4[1]),
            y[2] + w * (k1[2] + 2.0 * (k2[2] + k3[2]) + k4[2]), y[3] + w * (k1[3] + 2.0 * (k2[3] + k3[3]) + k4[3]),
            y[4] + w * (k1[4] + 2.0 * (k2[4] + k3[4]) + k4[4]))


@njit(**OPTS)
def rk4(coef, dt, n_delay, n_steps, lyap):
    n_l, size, h, w = coef.shape[0], n_delay + 1, 0.5 * dt, dt / 6.0
    # ring rows 2 p, 2 p + 1: m_x, m_y at slot p
    st, ring, e_ring, sc = _buffers(2 * size * n_l, 2 * size * n_l, 12 * S)
    _start(coef, st)
    ring[:] = coef[0, 5]
    pos, logs, since = 0, 0.0, 0
    for _ in range(n_steps):
        b = uint64(2 * pos * n_l)
        for j in range(n_l):
            ring[b + uint64(j)] = st[MX * S + j]
            ring[b + uint64(n_l + j)] = st[MY * S + j]
        if lyap:
            for j in range(n_l):
                e_ring[b + uint64(j)] = st[EX * S + j]
                e_ring[b + uint64(n_l + j)] = st[EY * S + j]
        pos = pos + 1 if pos + 1 < size else 0
        nxt = pos + 1 if pos + 1 < size else 0
        b0, b1 = uint64(2 * pos * n_l), uint64(2 * nxt * n_l)
        if not lyap:
            for j in range(n_l):
                x0, x1 = ring[b0 + uint64(j)], ring[b1 + uint64(j)]
                xh = hermite_mid(x0, x1, ring[b0 + uint64(n_l + j)], ring[b1 + uint64(n_l + j)], dt)
                y, c = _y(st, j, MX), _y(st, j, CA)
                k1 = _f(y, x0, c)
                k2 = _f(_add(y, h, k1), xh, c)
                k3 = _f(_add(y, h, k2), xh, c)
                k4 = _f(_add(y, dt, k3), x1, c)
                _put(st, j, MX, _sum(y, w, k1, k2, k3, k4))
            continue
        for j in range(n_l):
            x0, x1 = ring[b0 + uint64(j)], ring[b1 + uint64(j)]
            st[X0 * S + j], st[X1 * S + j] = x0, x1
            st[XH * S + j] = hermite_mid(x0, x1, ring[b0 + uint64(n_l + j)], ring[b1 + uint64(n_l + j)], dt)
        for j in range(n_l):
            c0, c1 = e_ring[b0 + uint64(j)], e_ring[b1 + uint64(j)]
            st[E0 * S + j], st[E1 * S + j] = c0, c1
            st[EH * S + j] = hermite_mid(c0, c1, e_ring[b0 + uint64(n_l + j)], e_ring[b1 + uint64(n_l + j)], dt)
        for j in range(n_l):
            y, c = _y(st, j, MX), _y(st, j, CA)
            k1 = _f(y, st[X0 * S + j], c)
            y2 = _add(y, h, k1)
            k2 = _f(y2, st[XH * S + j], c)
            y3 = _add(y, h, k2)
            k3 = _f(y3, st[XH * S + j], c)
            y4 = _add(y, dt, k3)
            k4 = _f(y4, st[X1 * S + j], c)
            sc[j], sc[S + j], sc[2 * S + j] = y[1], y[3], y[4]
            sc[3 * S + j], sc[4 * S + j], sc[5 * S + j] = y2[1], y2[3], y2[4]
            sc[6 * S + j], sc[7 * S + j], sc[8 * S + j] = y3[1], y3[3], y3[4]
            sc[9 * S + j], sc[10 * S + j], sc[11 * S + j] = y4[1], y4[3], y4[4]
            _put(st, j, MX, _sum(y, w, k1, k2, k3, k4))
        for j in range(n_l):
            e, c = _y(st, j, EX), _y(st, j, CA)
            t1 = _t(_y3(sc, j, 0), e, st[E0 * S + j], c)
            t2 = _t(_y3(sc, j, 3), _add(e, h, t1), st[EH * S + j], c)
            t3 = _t(_y3(sc, j, 6), _add(e, h, t2), st[EH * S + j], c)
            t4 = _t(_y3(sc, j, 9), _add(e, dt, t3), st[E1 * S + j], c)
            _put(st, j, EX, _sum(e, w, t1, t2, t3, t4))
        since += 1
        if since == n_delay:  # renormalise every tau
            since = 0
            logs += _renormalise(n_l, st, e_ring, 2 * size, 2, dt)
    return st[:5 * S].reshape(5, S)[:, :n_l].copy(), logs
