"""Many parameter points that share tau in one numba call: the batched Euler and RK4 kernels.

One trajectory is a chain of dependent floating-point operations: each step waits for the
previous one, so a single run is bound by the latency of that chain (~6 ns per Euler step),
not by the machine's throughput. A batch advances up to ``LANES`` points ("lanes") side by
side, and the equations of one step are computed for all lanes in one loop that LLVM
vectorises (AVX-512: 8 lanes per instruction).

**Lanes share tau.** Points with the same tau (and solver settings) have the same grid
(core.solve.make_grid: step dt' = tau / N, delay N, length, samplers, renormalisation
interval), so they share one step counter and every event (a window or trace sample, a
tangent renormalisation, the end) falls on the same step for all of them. simulate_batch
groups the points it is given by grid; the workers claim runs of one tau together
(slopetui.store.runs.claims), and a plane of n x m points has n points per tau.

The layout is what lets LLVM vectorise the lane loop with plain vector loads and stores:

* the state is one flat array ``st`` of rows with a compile-time stride LANES
  (st[r * LANES + j]: row r of lane j), so LLVM proves the rows never overlap;
* the delay ring is delay-major: ring[pos * L + j] is m_x at ring slot pos for lane j
  (RK4: (m_x, m_y) as rows 2 pos and 2 pos + 1), so a step reads and writes one contiguous
  row of lanes, with no gather and no copying into blocks;
* ring indices are unsigned (a signed index would need a wraparound test per element);
* the trip count of the lane loop is a runtime value, so LLVM's loop vectoriser (not the
  SLP one) takes it;
* with lambda_max the tangent has its own lane loop (Euler), and RK4 writes the delay rows
  in a small loop of their own before the step reads them: one loop that both writes and
  reads the ring at rows only known at run time is not vectorised;
* the rings start half a row of lanes (256 bytes) away from st modulo 512 bytes, so that a
  load never waits on a recent store to another row at the same 12 low address bits
  (skewed_buffers, SKEW).

**Resumable.** A batch's whole state is arrays (start_batch: the state rows, the rings,
the samplers' and the batch's counters), which batch_steps reads and leaves at the step it
stops at, so that a batch continues in chunks as the single kernels do (core.methods).

**Events** (a tangent renormalisation, the end) are handled between chunks of steps: the
steps up to the next event of the group run as one tight loop (at most MAX_CHUNK steps),
then the event is handled for every lane. Samples are taken inside the chunk, at the step
they are due (one comparison per step).

**Blow-up** is marked without a branch in the vector loop: a lane whose state leaves the
bounds gets m_y = NaN, which every later step keeps (a row of first bad steps cost 15% of
Euler's loop). After the chunk such a lane leaves, the last active lane moving
into its column so that the loop stays dense, and simulate_batch computes it again with
the single kernel, which gives its exact step and results (runs that blow up are rare:
none in the (k, tau) plane; Fig. 7's low a).

**Realisability** (core.closure.Realisability): each lane keeps the running minima of s_x,
s_y and s_x s_y - u^2 in three rows of ``st``, updated by selects on the state each step
starts from (lowest_lane). The first violating step is found without a row of its own:
after each chunk a lane whose minima first crossed the tolerance records the chunk's end
(crossed), and _integrate runs the single kernel up to it for the exact step.

Each lane performs the same operations in the same order as the single kernel (core.euler,
core.rk4) on its run. Euler without lambda_max: its window, trace and blow-up step equal the
single kernel's bit for bit. RK4: LLVM fuses the multiply-adds of the vectorised loop (and of
its scalar remainder) a little differently from the single kernel's ("contract" in
core.model.JIT), so a lane agrees with it to rounding (1.4e-13 after 3e5 steps on the test
points, the same blow-up steps). With lambda_max the tangent's renormalisation also sums
each lane's ring in another order (across lanes, row by row, where the single kernel keeps
four partial sums). tests/unit/test_batch.py checks each, and that regimes and lambda_max
agree.

Measured against a minimal kernel of each shape (benchmarks/yardstick.py) by
benchmarks/bench_kernels.py: see docs/speed.md. The RK4 + lambda_max loop spills many of
its stages to the stack, and its speed depends on where the calling thread's stack lies:
in a process's main thread, whose stack starts at a random offset within its page, it
took 9.2-14.1 ns per point-step from one process to the next; in a thread of its own, as
the workers call it, 8.9-10.3 (the benchmark's docstring). Presumably 4K aliasing between
the spills and the rows of st and the rings, which cover every offset of a page; this
machine's virtual CPUs have no counters to confirm it.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import replace

import numpy as np
from numba import njit, uint64

from core.closure import REALISABLE_TOL, Realisability
from core.methods import method
from core.model import JIT, coefficients, rhs, rhs_tangent
from core.params import Params
from core.recording import blown_up
from core.rk4 import hermite_mid
from core.solve import Grid, SolverSettings, Trajectory, make_grid, moved_into, simulate, trajectory_of
from core.spare_buffers import sample_array

#: The engine's numba options, with numpy's error model: Python's would test every
#: division (RK4's dt / 6) for zero, and a possible exception stops LLVM vectorising.
BATCH_JIT = {**JIT, "error_model": "numpy"}
#: Lanes of one kernel call, and the compile-time stride of the state's rows. 64 lanes are
#: 8 AVX-512 vectors: the per-step overhead (the ring position, the loop's set-up) is
#: shared by 64 point-steps. A prototype measured 1.09 ns per point-step at 64 lanes and
#: 1.14 at 32 (Euler, tau = 10, one core).
LANES = 64
#: Doubles in one vector (AVX-512); a call's lanes are padded to whole vectors (_integrate).
#: With AVX2 LLVM takes two vectors of 4 per iteration: 8 suits both.
VECTOR = 8
#: A group of fewer points goes to the single kernel, which is then faster. ns per point-step
#: (t_end 2000, RK4 2e4, tau = 10), single kernel against a padded batch of 2 / 3 / 4:
#: Euler 7.0 against 8.4 / 5.8 / 4.2, Euler + lambda_max 9.1 against 19 / 13 / 8.4, RK4
#: 30 against 32 / 21 / 15, RK4 + lambda_max 46 against 88 / 58 / 40.
MIN_LANES = 4
#: A lane that blew up stops costing work after at most this many steps.
MAX_CHUNK = 1024
#: done of a lane that blew up: simulate_batch computes it again with the single kernel,
#: which finds the exact step (euler_steps).
AGAIN = -1

# Rows of the flat state ``st`` (row r of lane j is st[r * LANES + j]): the five variables,
# their tangents, the coefficients (a, q, F1, k, d) and the running minima of s_x, s_y and
# s_x s_y - u^2 (lowest_lane).
(M_X, M_Y, S_X, S_Y, U, E_X, E_Y, E_SX, E_SY, E_U, CA, CQ, CF1, CK, CD, LO_X, LO_Y, LO_D) = range(18)
N_ROWS = 18


@njit(**BATCH_JIT)
def start_lanes(n_lanes, coef, st):
    """Lane j at t = 0: eq. (19), the tangent as core.euler starts it, its coefficients."""
    for j in range(n_lanes):
        delta = coef[j, 5]
        for r in range(M_X, U + 1):
            st[r * LANES + j] = delta                         # (19)
        st[E_X * LANES + j] = 0.0
        for r in range(E_Y, E_U + 1):
            st[r * LANES + j] = 1.0
        for r in range(5):
            st[(CA + r) * LANES + j] = coef[j, r]
        for r in range(LO_X, LO_D + 1):
            st[r * LANES + j] = np.inf


@njit(**BATCH_JIT)
def euler_steps(m, n, n_a, width, st, ring, e_ring, pos, size, n_delay, dt, lyap, due, smp,
                win, trace, lane_of):
    """m Euler steps from step n of the n_a active lanes (core.euler's loop body), with the
    samples due on the way (take_samples, from step ``due``); returns the ring position
    after them and the next step a sample is due.

    Ring row pos holds m_x(t - tau) and gets m_x(t), as in core.euler (one row read and
    written in place: a row read and another written cost 25% more); without delay (tau =
    0) m_x itself is the delayed value. A lane out of bounds is marked by m_y = NaN, which
    every later step keeps: the cheapest mark (a select; a row of first bad steps cost
    15% more). The test is on the state the step starts from, whose values the step loads
    anyway: 5-7% faster than testing the state it computes (0.97 against 1.02-1.05 times
    the yardstick's loop, two runs of 12 interleaved rounds), and a lane is still marked
    once its state leaves the bounds, a step later, or by drop_blown after the chunk's
    last step. Such a lane is computed again by the single kernel, which gives its exact
    blow-up step: keeping the rows a chunk reads, to compute the chunk again, cost more
    than the mark saved (2.4 ns per point-step against 1.1), and a second row to write (a
    ring a chunk longer, which a chunk never overwrites as it reads) 25%."""
    delayed = n_delay > 0
    for i in range(m):
        if n + i == due:
            due = take_samples(n + i, n_a, st, smp, win, trace, lane_of)
        row = uint64(pos) * uint64(width)
        if lyap:
            for j in range(n_a):
                e_x, e_ring_x = st[E_X * LANES + j], e_ring[row + uint64(j)]
                e_tau = e_ring_x if delayed else e_x
                e_ring[row + uint64(j)] = e_x
                f = rhs_tangent(st[M_Y * LANES + j], st[S_Y * LANES + j], st[U * LANES + j],
                                e_x, st[E_Y * LANES + j], st[E_SX * LANES + j],
                                st[E_SY * LANES + j], st[E_U * LANES + j], e_tau,
                                st[CA * LANES + j], st[CQ * LANES + j], st[CF1 * LANES + j],
                                st[CK * LANES + j])
                st[E_X * LANES + j] = e_x + dt * f[0]
                st[E_Y * LANES + j] += dt * f[1]
                st[E_SX * LANES + j] += dt * f[2]
                st[E_SY * LANES + j] += dt * f[3]
                st[E_U * LANES + j] += dt * f[4]
        for j in range(n_a):  # (6a-6e)
            m_x, ring_x = st[M_X * LANES + j], ring[row + uint64(j)]
            m_y, s_y = st[M_Y * LANES + j], st[S_Y * LANES + j]
            m_x_tau = ring_x if delayed else m_x
            ring[row + uint64(j)] = m_x
            s_x, u = st[S_X * LANES + j], st[U * LANES + j]
            lowest_lane(st, j, s_x, s_y, u)
            f = rhs(m_x, m_y, s_x, s_y, u, m_x_tau,
                    st[CA * LANES + j], st[CQ * LANES + j], st[CF1 * LANES + j],
                    st[CK * LANES + j], st[CD * LANES + j])
            st[M_X * LANES + j] = m_x + dt * f[0]
            st[M_Y * LANES + j] = np.nan if blown_up(m_y, s_y) else m_y + dt * f[1]
            st[S_X * LANES + j] = s_x + dt * f[2]
            st[S_Y * LANES + j] = s_y + dt * f[3]
            st[U * LANES + j] = u + dt * f[4]
        pos += 1
        if pos == size:
            pos = 0
    return pos, due


@njit(**BATCH_JIT)
def rk4_steps(m, n, n_a, width, st, ring, e_ring, pos, size, n_delay, dt, lyap, due, smp,
              win, trace, lane_of):
    """m RK4 steps from step n of the n_a active lanes (core.rk4's loop body), with the
    samples due on the way (as euler_steps); returns the ring position after them and the
    next step a sample is due. Ring rows 2 pos, 2 pos + 1 get (m_x, m_y) at step n; the
    stages read steps n - N and n - N + 1 (slots old and nxt), or, while t_n + dt - tau <=
    0, the history slot ``size`` twice (batch: (delta, 0), the tangent's (0, 0)), from which
    hermite_mid gives delta (0) exactly: the choice is a row, made once a step, not a select
    of every delayed value (core.rk4 does not interpolate across t = 0 either, where the
    history's slope 0 meets m_y(0) = delta). A lane out of bounds is marked by m_y = NaN,
    tested on the state the step starts from, as euler_steps does. These two replaced the
    selects and a row of first bad steps: 3.97 against 4.33 ns per point-step on the step
    loop without lambda_max (64 lanes, tau = 10, 5 interleaved rounds).

    Each step is the ring writes (a small loop per ring: one loop that both writes and reads
    a ring at rows only known at run time is not vectorised), then one lane loop that reads
    the delayed values from the rings itself and does the step. With lambda_max that loop
    does stage i of the state, then stage i of the tangent (K_i = J(X_i) (e + c_i dt
    K_{i-1}) + J_tau e_tau) from X_i's values in registers: the two dependency chains side
    by side keep the core busy (RK4 + lambda_max, 64 lanes, tau 5-10, kernel only: 9.5-10.4
    ns per point-step, against 11.1-12.0 with the delayed values and the state's stages
    passed through rows of ``st`` and a scratch array to a tangent loop of its own, and
    12.0 with the tangent's four stages after the state's in the same loop, which spills
    less but chains them one after the other; two lanes per iteration spilled most: 15.9).
    LLVM checks the rings against ``st`` at run time, once per loop.
    The step is written out in the loop, with small helpers only: LLVM vectorises a loop
    once everything in it is inlined, and it did not inline a whole RK4 lane step as one
    function (numba's inline="always" neither), which left the loop scalar (33 ns)."""
    delayed = n_delay > 0
    h, w = 0.5 * dt, dt / 6.0
    for i in range(m):
        if n + i == due:
            due = take_samples(n + i, n_a, st, smp, win, trace, lane_of)
        base = uint64(2 * pos) * uint64(width)
        write_ring(n_a, width, base, st, M_X, ring)
        if lyap:
            write_ring(n_a, width, base, st, E_X, e_ring)
        old = pos + 1 if pos + 1 < size else 0   # step n - N
        nxt = old + 1 if old + 1 < size else 0   # step n - N + 1
        pos = old
        if n + i < n_delay:  # t_n + dt - tau <= 0: the history slot
            old = nxt = size
        b_old, b_nxt = uint64(2 * old) * uint64(width), uint64(2 * nxt) * uint64(width)
        # lyap chooses between two loops, not inside one (LLVM does not unswitch a loop this
        # large). Without it the step reads the ring itself (4.9 ns per point-step, 7.3
        # through rows of st).
        if not lyap:
            for j in range(n_a):
                y, c = state(st, j, M_X), coefs(st, j)
                lowest_lane(st, j, y[2], y[3], y[4])
                x = delayed_values(ring, b_old, b_nxt, width, j, dt)
                k1 = field(y, x[0] if delayed else y[0], c)
                y2 = stage(y, h, k1)
                k2 = field(y2, x[1] if delayed else y2[0], c)
                y3 = stage(y, h, k2)
                k3 = field(y3, x[1] if delayed else y3[0], c)
                y4 = stage(y, dt, k3)
                k4 = field(y4, x[2] if delayed else y4[0], c)
                put(st, M_X, j, marked(y, combine(y, w, k1, k2, k3, k4)))
        else:
            for j in range(n_a):  # the state's and the tangent's stages side by side
                y, c, e = state(st, j, M_X), coefs(st, j), state(st, j, E_X)
                lowest_lane(st, j, y[2], y[3], y[4])
                x = delayed_values(ring, b_old, b_nxt, width, j, dt)
                ex = delayed_values(e_ring, b_old, b_nxt, width, j, dt)
                k1 = field(y, x[0] if delayed else y[0], c)
                t1 = tangent_field(slopes(y), e, ex[0] if delayed else e[0], c)
                y2, g = stage(y, h, k1), stage(e, h, t1)
                k2 = field(y2, x[1] if delayed else y2[0], c)
                t2 = tangent_field(slopes(y2), g, ex[1] if delayed else g[0], c)
                y3, g = stage(y, h, k2), stage(e, h, t2)
                k3 = field(y3, x[1] if delayed else y3[0], c)
                t3 = tangent_field(slopes(y3), g, ex[1] if delayed else g[0], c)
                y4, g = stage(y, dt, k3), stage(e, dt, t3)
                k4 = field(y4, x[2] if delayed else y4[0], c)
                t4 = tangent_field(slopes(y4), g, ex[2] if delayed else g[0], c)
                put(st, M_X, j, marked(y, combine(y, w, k1, k2, k3, k4)))
                put(st, E_X, j, combine(e, w, t1, t2, t3, t4))
    return pos, due


@njit(**BATCH_JIT)
def lowest_lane(st, j, s_x, s_y, u):
    """core.recording.lowest for lane j, in its rows LO_X, LO_Y, LO_D: the running minima
    of s_x, s_y and s_x s_y - u^2 with the state a step starts from (its values are loaded
    anyway), as selects that keep the loop vectorised. The first violating step is not
    kept here (a row of first steps is the select per step that cost Euler's loop 15%,
    see the module docstring): crossed marks the chunk after which a lane's minima first
    fall below the tolerance, and _integrate finds the step by the single kernel up to
    that chunk's end."""
    det = s_x * s_y - u * u
    lo = st[LO_X * LANES + j]
    st[LO_X * LANES + j] = s_x if s_x < lo else lo
    lo = st[LO_Y * LANES + j]
    st[LO_Y * LANES + j] = s_y if s_y < lo else lo
    lo = st[LO_D * LANES + j]
    st[LO_D * LANES + j] = det if det < lo else lo


@njit(**BATCH_JIT)
def crossed(n_a, st, lane_of, cross, n):
    """cross[lane] = n for every active lane whose minima fell below -REALISABLE_TOL for
    the first time in the steps before n (the first chunk that ends after its first
    violating step)."""
    for j in range(n_a):
        if cross[lane_of[j]] < 0 and (st[LO_X * LANES + j] < -REALISABLE_TOL
                                      or st[LO_Y * LANES + j] < -REALISABLE_TOL
                                      or st[LO_D * LANES + j] < -REALISABLE_TOL):
            cross[lane_of[j]] = n


@njit(**BATCH_JIT)
def field(y, x_tau, c):
    """(6a-6e) at the state y = (m_x, m_y, s_x, s_y, u) and delayed m_x x_tau, with the
    coefficients c = (a, q, F1, k, d)."""
    return rhs(y[0], y[1], y[2], y[3], y[4], x_tau, c[0], c[1], c[2], c[3], c[4])


@njit(**BATCH_JIT)
def tangent_field(y, e, e_tau, c):
    """The tangent-linear map at (m_y, s_y, u) = y applied to the tangent e and the delayed
    tangent e_tau."""
    return rhs_tangent(y[0], y[1], y[2], e[0], e[1], e[2], e[3], e[4], e_tau, c[0], c[1], c[2], c[3])


@njit(**BATCH_JIT)
def write_ring(n_a, width, base, st, first, ring):
    """Ring rows base, base + width (one slot) = rows first, first + 1 of st (m_x and m_y,
    or their tangents)."""
    for j in range(n_a):
        ring[base + uint64(j)] = st[first * LANES + j]
        ring[base + uint64(width + j)] = st[(first + 1) * LANES + j]


@njit(**BATCH_JIT)
def delayed_values(ring, b_old, b_nxt, width, j, dt):
    """The delayed value of lane j at the step's three stage times (t - tau, its half step,
    t + dt - tau), from the ring slots at rows b_old and b_nxt (core.rk4: the half step
    from the Hermite cubic, m_y being the slope of m_x)."""
    v0, v1 = ring[b_old + uint64(j)], ring[b_nxt + uint64(j)]
    vh = hermite_mid(v0, v1, ring[b_old + uint64(width + j)], ring[b_nxt + uint64(width + j)], dt)
    return v0, vh, v1


@njit(**BATCH_JIT)
def state(st, j, first):
    """Lane j's five variables (m_x, m_y, s_x, s_y, u) from row first = M_X, or their
    tangents from row first = E_X."""
    return (st[first * LANES + j], st[(first + 1) * LANES + j], st[(first + 2) * LANES + j],
            st[(first + 3) * LANES + j], st[(first + 4) * LANES + j])


@njit(**BATCH_JIT)
def coefs(st, j):
    """Lane j's coefficients (a, q, F1, k, d)."""
    return (st[CA * LANES + j], st[CQ * LANES + j], st[CF1 * LANES + j], st[CK * LANES + j],
            st[CD * LANES + j])


@njit(**BATCH_JIT)
def put(st, first, j, y):
    """Lane j's five rows from row ``first`` = y. (Spelled out: a loop over the tuple
    stopped LLVM vectorising the tangent's loop.)"""
    st[first * LANES + j] = y[0]
    st[(first + 1) * LANES + j] = y[1]
    st[(first + 2) * LANES + j] = y[2]
    st[(first + 3) * LANES + j] = y[3]
    st[(first + 4) * LANES + j] = y[4]


@njit(**BATCH_JIT)
def stage(y, c, k):
    """An RK4 stage's state y + c k."""
    return (y[0] + c * k[0], y[1] + c * k[1], y[2] + c * k[2], y[3] + c * k[3], y[4] + c * k[4])


@njit(**BATCH_JIT)
def slopes(y):
    """(m_y, s_y, u) of a stage's state y: what the tangent-linear map depends on."""
    return y[1], y[3], y[4]


@njit(**BATCH_JIT)
def marked(y0, y):
    """The step's new state y, with m_y = NaN if the state y0 it started from is out of
    bounds (rk4_steps)."""
    return y[0], np.nan if blown_up(y0[1], y0[3]) else y[1], y[2], y[3], y[4]


@njit(**BATCH_JIT)
def combine(y, w, k1, k2, k3, k4):
    """The RK4 step y + w (k1 + 2 (k2 + k3) + k4), w = dt / 6, as core.rk4 sums it."""
    return (y[0] + w * (k1[0] + 2.0 * (k2[0] + k3[0]) + k4[0]),
            y[1] + w * (k1[1] + 2.0 * (k2[1] + k3[1]) + k4[1]),
            y[2] + w * (k1[2] + 2.0 * (k2[2] + k3[2]) + k4[2]),
            y[3] + w * (k1[3] + 2.0 * (k2[3] + k3[3]) + k4[3]),
            y[4] + w * (k1[4] + 2.0 * (k2[4] + k3[4]) + k4[4]))


@njit(**BATCH_JIT)
def renormalise_lanes(n_a, width, st, e_ring, rows, shifted, dt, logs, lane_of, i_r):
    """core.recording.renormalise for every active lane at once: project out the neutral
    shift (e_x from m_x's ring rows, those with ``shifted`` row parity 0), measure the
    tangent with the delay ring's first ``rows`` rows weighted by dt, log its growth, scale
    it to 1.

    The sums run over the ring rows with the lanes inside: one contiguous row at a time,
    vectorised across lanes (the single kernel sums one lane's ring in 4 partial sums)."""
    acc = np.zeros(n_a)
    for r in range(rows):
        base = uint64(r) * uint64(width)
        shift = 1.0 if r % shifted == 0 else 0.0
        for j in range(n_a):
            h = e_ring[base + uint64(j)] - shift * st[E_X * LANES + j]
            acc[j] += h * h
    for j in range(n_a):
        e_y, e_sx = st[E_Y * LANES + j], st[E_SX * LANES + j]
        e_sy, e_u = st[E_SY * LANES + j], st[E_U * LANES + j]
        norm = np.sqrt(e_y * e_y + e_sx * e_sx + e_sy * e_sy + e_u * e_u + dt * acc[j])
        logs[lane_of[j], i_r] = np.log(norm)
        acc[j] = 1.0 / norm
    for r in range(rows):
        base = uint64(r) * uint64(width)
        shift = 1.0 if r % shifted == 0 else 0.0
        for j in range(n_a):
            e_ring[base + uint64(j)] = (e_ring[base + uint64(j)] - shift * st[E_X * LANES + j]) * acc[j]
    for j in range(n_a):
        st[E_X * LANES + j] = 0.0
        for r in range(E_Y, E_U + 1):
            st[r * LANES + j] *= acc[j]


# Fields of the samplers' state ``smp`` (int64): the window's next step, column, stride,
# jump and resume (core.solve.Grid: sample_start, win_stride, sample_jump, win_start) and
# columns; the trace's next step, column, stride and columns.
(W_NEXT, W_I, W_STRIDE, W_JUMP, W_RESUME, W_COUNT, T_NEXT, T_I, T_STRIDE, T_COUNT) = range(10)
#: "No sample is due any more": beyond every run's last step (core.solve.MAX_STEPS).
NEVER = 1 << 62


@njit(**BATCH_JIT)
def next_due(smp):
    """The next step at which the window or the trace takes a sample."""
    w = smp[W_NEXT] if smp[W_I] < smp[W_COUNT] else NEVER
    t = smp[T_NEXT] if smp[T_I] < smp[T_COUNT] else NEVER
    return min(w, t)


@njit(**BATCH_JIT)
def take_samples(n, n_a, st, smp, win, trace, lane_of):
    """The window and trace samples due at step n (the state before the step, as
    core.recording.sample takes it); returns the next step one is due. Samples are taken
    inside the chunks of steps, not as events between them: the window samples every
    step (RK4 at dt = 1e-2) or every 10 (Euler), and as events they cut the chunks to a
    step or ten (RK4 batched: 6.2 ns per point-step, against 4.6 without a window)."""
    if smp[W_NEXT] == n and smp[W_I] < smp[W_COUNT]:
        sample_lanes(n_a, st, win, smp[W_I], lane_of)
        smp[W_I] += 1
        smp[W_NEXT] = smp[W_RESUME] if smp[W_I] == smp[W_JUMP] else smp[W_NEXT] + smp[W_STRIDE]
    if smp[T_NEXT] == n and smp[T_I] < smp[T_COUNT]:
        sample_lanes(n_a, st, trace, smp[T_I], lane_of)
        smp[T_I] += 1
        smp[T_NEXT] += smp[T_STRIDE]
    return next_due(smp)


@njit(**BATCH_JIT)
def sample_lanes(n_a, st, out, i, lane_of):
    """Column i of every active lane's sampler ``out`` (rows of 5 values per lane): the
    state at this step, as core.recording.sample stores it."""
    for j in range(n_a):
        for v in range(5):
            out[lane_of[j], i, v] = st[(M_X + v) * LANES + j]


@njit(**BATCH_JIT)
def drop_blown(n_a, width, st, ring, e_ring, lane_of, done):
    """After a chunk, the lanes marked out of bounds (m_y = NaN), or whose state after the
    chunk's last step is (the kernels test the state a step starts from), leave, to be
    computed again by the single kernel (done = AGAIN); the last active lane takes each
    one's column, ring column included. Returns the number of active lanes."""
    j = 0
    while j < n_a:
        if not blown_up(st[M_Y * LANES + j], st[S_Y * LANES + j]):  # NaN counts as out
            j += 1
            continue
        done[lane_of[j]] = AGAIN
        n_a -= 1
        for r in range(N_ROWS):
            st[r * LANES + j] = st[r * LANES + n_a]
        for r in range(ring.shape[0] // width):
            ring[r * width + j] = ring[r * width + n_a]
        for r in range(e_ring.shape[0] // width):
            e_ring[r * width + j] = e_ring[r * width + n_a]
        lane_of[j] = lane_of[n_a]
    return n_a


#: Where skewed_buffers starts the rings: 32 doubles (256 bytes) past a multiple of 512
#: bytes from the start of st, half a row of 64 lanes. A load whose address equals an
#: older, uncommitted store's in its 12 low bits waits for it ("4K aliasing"), and the
#: rows of st and of the rings are all 512 bytes apart (64 lanes): with a
#: ring at st's offset modulo 512, loading lane j of a state row after storing lane j of
#: a ring row aliases at every step; half a row away, a load meets a store four vectors
#: earlier or later, which has committed. Measured on the Euler loop (tau = 10, 64 lanes),
#: ns per point-step by the ring's offset from st modulo 4096: 0.91-1.04 at 256 modulo
#: 512, 1.01-1.21 at multiples of 512, 1.08-1.23 at 64 to 192 bytes. Separately allocated
#: buffers fell at a random offset, so the batched kernels' times varied by 15-25% from
#: one process to the next.
SKEW = 32


@njit(**BATCH_JIT)
def skewed_buffers(n_ring, n_e_ring):
    """The state ``st``, the ring and the tangent's ring, zeros, in one allocation, each ring
    starting SKEW doubles past a multiple of a row of LANES from the start of st (see
    SKEW)."""
    n_st = N_ROWS * LANES
    a = n_st + (SKEW - n_st) % LANES
    b = a + n_ring + (SKEW - a - n_ring) % LANES
    buf = np.zeros(b + n_e_ring)
    return buf[:n_st], buf[a:a + n_ring], buf[b:b + n_e_ring]


@njit(**BATCH_JIT)
def batch(rk4, coef, dt, n_delay, n_steps, sampler, trace_stride, lyap, renorm, win, trace,
          logs, done, lows, cross):
    """Integrate every lane (row of coef, at most LANES) on one grid to its end or blow-up;
    done[lane] gets its number of steps, as the single kernels return.

    lows (lanes, 3): the minima of s_x, s_y and s_x s_y - u^2 over every step of a lane
    that reached its end (lowest_lane); cross (lanes, -1 filled): the end of the chunk in
    which they first fell below -REALISABLE_TOL (crossed), -1 if never.

    sampler: the window's (first step, stride, jump, resume) (core.solve.Grid: sample_start,
    win_stride, sample_jump, win_start). win, trace: (lanes, columns, 5). logs: (lanes,
    renormalisations), filled only if lyap.
    """
    st, ring, e_ring, smp, lane_of, at = start_batch(rk4, coef, n_delay, sampler, trace_stride,
                                                     lyap, renorm, win, trace)
    batch_steps(rk4, dt, n_delay, n_steps, n_steps, lyap, renorm, st, ring, e_ring, smp,
                lane_of, at, win, trace, logs, done, lows, cross)


# Fields of a batch's counters ``at`` (int64; start_batch, batch_steps): the step, the ring
# position, the active lanes, the next step a sample is due, the next renormalisation's
# log index and step.
(B_N, B_POS, B_ACTIVE, B_DUE, B_I_R, B_R_NEXT) = range(6)


@njit(**BATCH_JIT)
def ring_size(rk4, n_delay):
    """Slots of a batch's ring: RK4's (m_x, m_y) at steps n - N..n, Euler's m_x over
    (t - tau, t] (one slot without delay)."""
    return n_delay + 1 if rk4 else max(n_delay, 1)


@njit(**BATCH_JIT)
def start_batch(rk4, coef, n_delay, sampler, trace_stride, lyap, renorm, win, trace):
    """A batch's whole state at t = 0 (eq. 19 in every lane): (st, ring, e_ring, smp,
    lane_of, at), what batch_steps continues from."""
    n_lanes = coef.shape[0]
    lane_of = np.arange(n_lanes)
    width = n_lanes
    # rk4: (m_x, m_y) at steps n - N..n, rows 2 pos and 2 pos + 1, and the history slot
    # ``size`` after them (rk4_steps); Euler: m_x over (t - tau, t], the history before
    # t = 0 being delta (core.history)
    size = ring_size(rk4, n_delay)
    n_ring = 2 * (size + 1) * width if rk4 else size * width
    st, ring, e_ring = skewed_buffers(n_ring, n_ring if lyap else 0)
    start_lanes(n_lanes, coef, st)
    # the history before t = 0: RK4's slot ``size`` holds (delta, 0), Euler's whole ring delta
    first, last = (2 * size, 2 * size + 1) if rk4 else (0, size)
    for r in range(first, last):
        ring[r * width:r * width + n_lanes] = coef[:, 5]
    smp = np.array([sampler[0], 0, sampler[1], sampler[2], sampler[3], win.shape[1],
                    0, 0, trace_stride, trace.shape[1]], dtype=np.int64)
    at = np.array([0, 0, n_lanes, next_due(smp), 0, renorm], dtype=np.int64)
    return st, ring, e_ring, smp, lane_of, at


@njit(**BATCH_JIT)
def batch_steps(rk4, dt, n_delay, n_steps, stop, lyap, renorm, st, ring, e_ring, smp, lane_of,
                at, win, trace, logs, done, lows, cross):
    """Integrate the batch from its state (start_batch's arrays, ``at`` its counters) to
    step ``stop`` or, at n_steps, to its end (batch's outputs), and leave the state there:
    a batch continued from step to step gives each lane what one call gives (the kernel
    contract, core.methods, item 6), but for ``cross``, which is then a chunk end no later
    than one call's (_realisability finds the exact step from either)."""
    width = lane_of.shape[0]
    size = ring_size(rk4, n_delay)
    # the ring rows in the tangent's norm: RK4's N + 1 slots (two rows each), Euler's N,
    # none without delay (core.euler's empty history)
    rows = 2 * size if rk4 else n_delay
    n, pos, n_a, due = at[B_N], at[B_POS], at[B_ACTIVE], at[B_DUE]
    i_r, r_next = at[B_I_R], at[B_R_NEXT]
    while n_a > 0:
        if lyap and n == r_next:
            if rk4:  # the stale slot (step n - N - 1) must vanish from the norm
                row = 2 * pos * width
                for j in range(n_a):
                    e_ring[row + j] = st[E_X * LANES + j]
                    e_ring[row + width + j] = 0.0
            renormalise_lanes(n_a, width, st, e_ring, rows, 2 if rk4 else 1, dt, logs, lane_of,
                              i_r)
            i_r += 1
            r_next += renorm
        if n == n_steps:
            if due == n:
                take_samples(n, n_a, st, smp, win, trace, lane_of)
            for j in range(n_a):  # the final state, as the single kernels count it
                lowest_lane(st, j, st[S_X * LANES + j], st[S_Y * LANES + j], st[U * LANES + j])
            crossed(n_a, st, lane_of, cross, n_steps)
            for j in range(n_a):
                done[lane_of[j]] = n_steps
                for v in range(3):
                    lows[lane_of[j], v] = st[(LO_X + v) * LANES + j]
            break
        if n >= stop:
            break
        end = min(n_steps, n + MAX_CHUNK, stop)
        if lyap:
            end = min(end, r_next)
        if rk4:
            pos, due = rk4_steps(end - n, n, n_a, width, st, ring, e_ring, pos, size, n_delay,
                                 dt, lyap, due, smp, win, trace, lane_of)
        else:
            pos, due = euler_steps(end - n, n, n_a, width, st, ring, e_ring, pos, size,
                                   n_delay, dt, lyap, due, smp, win, trace, lane_of)
        n_a = drop_blown(n_a, width, st, ring, e_ring, lane_of, done)
        crossed(n_a, st, lane_of, cross, end)
        n = end
    at[B_N], at[B_POS], at[B_ACTIVE], at[B_DUE], at[B_I_R], at[B_R_NEXT] = n, pos, n_a, due, i_r, r_next


def simulate_batch(points: Sequence[Params], s: SolverSettings | None = None) -> list[Trajectory]:
    """Integrate every point with the same settings in batched numba calls.

    Returns one Trajectory per point, in order, equal to ``core.solve.simulate(p, s)``.
    Points are grouped by grid (their tau), and each group is integrated LANES points at a
    time (a group of fewer than MIN_LANES by the single kernel); each run's runtime_s is
    its call's wall time shared in proportion to its steps.
    The lanes start from eq. 19's constant history only (core.history): a run with
    another history is computed alone (the queue batches runs of one history).
    """
    s = s or SolverSettings()
    if s.history != "constant":
        raise ValueError(f"the batched kernels start from the constant history only, not "
                         f"{s.history!r}: compute such runs with core.solve.simulate")
    if not method(s.method).batched:  # no lane kernel (core.methods): one run after another
        return [simulate(p, s) for p in points]
    grids = [make_grid(p, s) for p in points]
    groups: dict[Grid, list[int]] = {}
    for i, g in enumerate(grids):
        groups.setdefault(g, []).append(i)
    out: list[Trajectory | None] = [None] * len(points)
    for g, members in groups.items():
        if len(members) < MIN_LANES:
            for i in members:
                out[i] = simulate(points[i], s)
            continue
        for first in range(0, len(members), LANES):
            lanes = members[first:first + LANES]
            for i, tr in zip(lanes, _integrate(g, [points[i] for i in lanes], s), strict=True):
                out[i] = tr
    return [tr for tr in out if tr is not None]


def _integrate(g: Grid, points: list[Params], s: SolverSettings) -> list[Trajectory]:
    """One kernel call: up to LANES points on grid g."""
    n_real = len(points)
    # Padded with copies of the last point to whole vectors: LLVM computes the lanes past
    # the last whole vector one by one (its scalar remainder), at the single kernel's cost,
    # where a padded vector computes them at once. An adaptive sweep's refined levels have
    # a few points per tau (the (k, tau) plane at 100 x 100: batches of 2-13).
    points = points + points[-1:] * (-n_real % VECTOR)
    n_lanes = len(points)
    # A lane's samples are rows of 5 values: one stream of writes per lane; trajectories get
    # (5, n) views. Every sample up to a lane's end or blow-up is written (trajectory_of
    # keeps no more), so no NaN fill is needed, and the arrays of an earlier call that
    # nothing refers to any more are written again (core.spare_buffers).
    win = sample_array((n_lanes, g.n_samples, 5))
    trace = sample_array((n_lanes, g.n_trace, 5))
    n_logs = g.n_steps // g.renorm_steps if s.lyap else 0
    logs = np.zeros((n_lanes, n_logs))
    done = np.zeros(n_lanes, dtype=np.int64)
    lows = np.zeros((n_lanes, 3))
    cross = np.full(n_lanes, -1, dtype=np.int64)
    sampler = np.array([g.sample_start, g.win_stride, g.sample_jump, g.win_start], dtype=np.int64)
    t0 = time.perf_counter()
    batch(s.method == "rk4", np.stack([coefficients(p) for p in points]), g.dt, g.n_delay,
          g.n_steps, sampler, g.trace_stride, s.lyap, g.renorm_steps, win, trace, logs, done,
          lows, cross)
    runtime = time.perf_counter() - t0
    share = np.maximum(done, 0) / max(1, int(np.maximum(done, 0).sum()))
    # A lane that blew up is computed again by the single kernel for its exact step
    # (euler_steps), and its run copied into the lane's columns, which no one else holds:
    # the batch's arrays stay alive as long as any lane's views, so a run kept in arrays of
    # its own would hold that lane's samples twice (one lane's at a time, here).
    return [moved_into(simulate(p, s), (win[j].T, trace[j].T, logs[j, :n_logs]))
            if done[j] == AGAIN else
            trajectory_of(p, s, g, int(done[j]), win[j].T, trace[j].T, logs[j, :n_logs],
                          runtime * share[j] * n_lanes / n_real,
                          _realisability(p, s, g, lows[j], int(cross[j])))
            for j, p in enumerate(points[:n_real])]


def _realisability(p: Params, s: SolverSettings, g: Grid, lows: np.ndarray,
                   cross: int) -> Realisability:
    """A lane's minima, and its first violation: the single kernel's, run without
    lambda_max (which leaves the state alone) up to the end of the chunk in which the
    lane's minima first fell below the tolerance (batch: cross). Euler's lanes cross in
    their first chunk (at t = 0.001 at the defaults), so this costs at most MAX_CHUNK
    steps there; a lane that crosses late costs as many steps again, once."""
    t_first = None
    if cross >= 0:
        head = simulate(p, replace(s, t_end=cross * g.dt, window=None, lyap=False, trace_points=2))
        t_first = head.realisability.t_first if head.realisability is not None else None
        if t_first is None:  # RK4 rounds a little differently (module docstring): a bound
            t_first = cross * g.dt
    return Realisability(float(lows[0]), float(lows[1]), float(lows[2]), t_first)
