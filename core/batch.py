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

**Lanes that stop early** (simulate_batch's ``finished``, _Lanes). After every chunk of
CHUNK_T time units a predicate sees each lane's trajectory so far and may retire it; a lane
that stops, reaches its t_end or blows up leaves its column (remove_lane), which takes the
batch's next waiting point at the next chunk end (fill_lane), or is padding up to a whole
vector (pad_lanes) when none waits. Lanes then run at different model times: each has its
own step 0 (li: OFF) and samplers, counted in its own steps; its start is a renormalisation
step of the batch, so that the tangent's renormalisations stay events of the whole batch;
the tangent's norm sums the ring in the slots' age order; RK4's history read of a late
start goes through its ring (fill_lane). Each run is then, bit for bit, its run in a batch
without stops, up to where it stopped (tests/unit/test_batch_refill.py).

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

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import replace
from typing import TypeVar

import numpy as np
from numba import njit, uint64

from core import chunk_state as cs
from core.chunk_state import ChunkState
from core.closure import REALISABLE_TOL, Realisability
from core.methods import method
from core.model import JIT, coefficients, rhs, rhs_tangent
from core.params import Params
from core.recording import blown_up
from core.rk4 import hermite_mid
from core.solve import Grid, SolverSettings, Trajectory, make_grid, moved_into, simulate, trajectory_of, window_times
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
# RK4's history patch (patches): the m_y and e_y it took out of the ring, put back a step later
(SV_Y, SV_EY) = (18, 19)
N_ROWS = 20


@njit(**BATCH_JIT)
def start_lane(j, c, st):
    """Lane j at its t = 0: eq. (19), the tangent as core.euler starts it, its coefficients
    c = (a, q, F1, k, d, delta)."""
    delta = c[5]
    for r in range(M_X, U + 1):
        st[r * LANES + j] = delta                         # (19)
    st[E_X * LANES + j] = 0.0
    for r in range(E_Y, E_U + 1):
        st[r * LANES + j] = 1.0
    for r in range(5):
        st[(CA + r) * LANES + j] = c[r]
    for r in range(LO_X, LO_D + 1):
        st[r * LANES + j] = np.inf


@njit(**BATCH_JIT)
def euler_steps(m, n, n_a, n_w, width, st, ring, e_ring, pos, size, n_delay, dt, lyap, due,
                li, win, trace, lane_of):
    """m Euler steps from step n of the first n_w lanes (core.euler's loop body: the n_a
    active ones and the padding after them, see pad_lanes), with the samples due on the
    way (take_samples, from step ``due``); returns the ring position after them and the
    next step a sample is due.

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
            due = take_samples(n + i, n_a, st, li, win, trace, lane_of)
        row = uint64(pos) * uint64(width)
        if lyap:
            for j in range(n_w):
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
        for j in range(n_w):  # (6a-6e)
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
def rk4_steps(m, n, n_a, n_w, width, st, ring, e_ring, pos, size, n_delay, dt, lyap, due, li,
              win, trace, lane_of):
    """m RK4 steps from step n of the first n_w lanes (core.rk4's loop body), with the
    samples due on the way (as euler_steps); returns the ring position after them and the
    next step a sample is due. Ring rows 2 pos, 2 pos + 1 get (m_x, m_y) at step n; the
    stages read steps n - N and n - N + 1 (slots old and nxt), or, while t_n + dt - tau <=
    0, the history slot ``size`` twice (batch: (delta, 0), the tangent's (0, 0)), from which
    hermite_mid gives delta (0) exactly: the choice is a row, made once a step, not a select
    of every delayed value; a lane started after step 0 reads its own ring, filled with the
    same values (fill_lane) (core.rk4 does not interpolate across t = 0 either, where the
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
            due = take_samples(n + i, n_a, st, li, win, trace, lane_of)
        base = uint64(2 * pos) * uint64(width)
        write_ring(n_w, width, base, st, M_X, ring)
        if lyap:
            write_ring(n_w, width, base, st, E_X, e_ring)
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
            for j in range(n_w):
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
            for j in range(n_w):  # the state's and the tangent's stages side by side
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
def crossed(n_a, st, li, lane_of, cross, n):
    """cross[lane] = n (in the lane's steps) for every active lane whose minima fell below
    -REALISABLE_TOL for the first time in the steps before the batch's step n (the first
    chunk that ends after its first violating step)."""
    for j in range(n_a):
        if cross[lane_of[j]] < 0 and (st[LO_X * LANES + j] < -REALISABLE_TOL
                                      or st[LO_Y * LANES + j] < -REALISABLE_TOL
                                      or st[LO_D * LANES + j] < -REALISABLE_TOL):
            cross[lane_of[j]] = n - li[j, OFF]


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
def renormalise_lanes(n_a, n_w, width, st, e_ring, rows, oldest, shifted, dt, logs, lane_of,
                      li, i_r, renorm):
    """core.recording.renormalise for the first n_w lanes at once: project out the neutral
    shift (e_x from m_x's ring rows, those with ``shifted`` row parity 0), measure the
    tangent with the delay ring's ``rows`` rows weighted by dt, log its growth (the n_a
    active lanes: renormalisation i_r of the batch is a lane's i_r - OFF / renorm, its
    start being a renormalisation step, fill_lane), scale it to 1.

    The sums run over the ring rows with the lanes inside: one contiguous row at a time,
    vectorised across lanes (the single kernel sums one lane's ring in 4 partial sums).
    They start at the row ``oldest`` (the oldest slot's) and wrap around: in the order of
    the slots' age, which is the same for every lane whatever step it started at, so that
    a lane refilled in the middle of a batch sums its ring as it would from step 0."""
    acc = np.zeros(n_w)
    for q in range(rows):
        r = oldest + q if oldest + q < rows else oldest + q - rows
        base = uint64(r) * uint64(width)
        shift = 1.0 if r % shifted == 0 else 0.0
        for j in range(n_w):
            h = e_ring[base + uint64(j)] - shift * st[E_X * LANES + j]
            acc[j] += h * h
    for j in range(n_w):
        e_y, e_sx = st[E_Y * LANES + j], st[E_SX * LANES + j]
        e_sy, e_u = st[E_SY * LANES + j], st[E_U * LANES + j]
        norm = np.sqrt(e_y * e_y + e_sx * e_sx + e_sy * e_sy + e_u * e_u + dt * acc[j])
        if j < n_a:
            logs[lane_of[j], i_r - li[j, OFF] // renorm] = np.log(norm)
        acc[j] = 1.0 / norm
    for r in range(rows):
        base = uint64(r) * uint64(width)
        shift = 1.0 if r % shifted == 0 else 0.0
        for j in range(n_w):
            e_ring[base + uint64(j)] = (e_ring[base + uint64(j)] - shift * st[E_X * LANES + j]) * acc[j]
    for j in range(n_w):
        st[E_X * LANES + j] = 0.0
        for r in range(E_Y, E_U + 1):
            st[r * LANES + j] *= acc[j]


# Fields of a lane's row of ``li`` (int64; a row per column of st, moving with it): its
# samplers, in the lane's own steps (the batch's step minus OFF): the window's next step,
# column, stride, jump and resume (core.solve.Grid: sample_start, win_stride, sample_jump,
# win_start) and columns; the trace's next step, column, stride and columns. Then OFF, the
# batch's step at which the lane started (its step 0), and RK4's history patch of a lane
# refilled after step 0 (fill_lane): PATCH its state (0 none, 1 due, 2 to undo) and
# P_STEP the batch's step at which it is due, P_SLOT the ring slot of the lane's step 0.
(W_NEXT, W_I, W_STRIDE, W_JUMP, W_RESUME, W_COUNT, T_NEXT, T_I, T_STRIDE, T_COUNT,
 OFF, PATCH, P_STEP, P_SLOT) = range(14)
LI_FIELDS = 14
#: "No sample is due any more": beyond every run's last step (core.solve.MAX_STEPS).
NEVER = 1 << 62


@njit(**BATCH_JIT)
def next_due(li, j):
    """The batch's step at which lane j's window or trace next takes a sample."""
    w = li[j, W_NEXT] if li[j, W_I] < li[j, W_COUNT] else NEVER
    t = li[j, T_NEXT] if li[j, T_I] < li[j, T_COUNT] else NEVER
    return li[j, OFF] + min(w, t)


@njit(**BATCH_JIT)
def take_samples(n, n_a, st, li, win, trace, lane_of):
    """The window and trace samples due at the batch's step n (the state before the step,
    as core.recording.sample takes it); returns the next step one is due. Samples are taken
    inside the chunks of steps, not as events between them: the window samples every
    step (RK4 at dt = 1e-2) or every 10 (Euler), and as events they cut the chunks to a
    step or ten (RK4 batched: 6.2 ns per point-step, against 4.6 without a window).
    Each lane has its samplers (its start may differ, fill_lane): the test per lane is a
    comparison on a due step, against the steps between two due steps."""
    due = NEVER
    for j in range(n_a):
        k = n - li[j, OFF]
        sample_due(j, k, st, li, win, trace, lane_of)
        due = min(due, next_due(li, j))
    return due


@njit(inline="always", **BATCH_JIT)
def sample_due(j, k, st, li, win, trace, lane_of):
    """Lane j's window and trace samples due at its step k, and its samplers moved on to
    the next: take_samples' inside the chunks, settle_lane's at a chunk's end."""
    if li[j, W_NEXT] == k and li[j, W_I] < li[j, W_COUNT]:
        sample_lane(j, st, win, li[j, W_I], lane_of)
        li[j, W_I] += 1
        li[j, W_NEXT] = li[j, W_RESUME] if li[j, W_I] == li[j, W_JUMP] else li[j, W_NEXT] + li[j, W_STRIDE]
    if li[j, T_NEXT] == k and li[j, T_I] < li[j, T_COUNT]:
        sample_lane(j, st, trace, li[j, T_I], lane_of)
        li[j, T_I] += 1
        li[j, T_NEXT] += li[j, T_STRIDE]


@njit(**BATCH_JIT)
def sample_lane(j, st, out, i, lane_of):
    """Column i of lane j's sampler ``out`` (rows of 5 values per lane): the state at this
    step, as core.recording.sample stores it."""
    for v in range(5):
        out[lane_of[j], i, v] = st[(M_X + v) * LANES + j]


@njit(**BATCH_JIT)
def drop_blown(n_a, width, st, ring, e_ring, li, lane_of, done):
    """After a chunk, the lanes marked out of bounds (m_y = NaN), or whose state after the
    chunk's last step is (the kernels test the state a step starts from), leave, to be
    computed again by the single kernel (done = AGAIN). Returns the number of active lanes."""
    j = 0
    while j < n_a:
        if not blown_up(st[M_Y * LANES + j], st[S_Y * LANES + j]):  # NaN counts as out
            j += 1
            continue
        done[lane_of[j]] = AGAIN
        n_a = remove_lane(j, n_a, width, st, ring, e_ring, li, lane_of)
    return n_a


@njit(**BATCH_JIT)
def remove_lane(j, n_a, width, st, ring, e_ring, li, lane_of):
    """Lane j leaves: the last active lane takes its column (state, ring columns, li row),
    so that the active lanes stay the first n_a columns; the columns after them up to a
    whole vector are padded again (pad_lanes). Returns the number of active lanes."""
    n_a -= 1
    copy_lane(n_a, j, width, st, ring, e_ring, li, lane_of)
    pad_lanes(n_a, width, st, ring, e_ring, li, lane_of)
    return n_a


@njit(**BATCH_JIT)
def copy_lane(src, dst, width, st, ring, e_ring, li, lane_of):
    """Column src's whole lane (state rows, ring columns, li row, point) into column dst."""
    for r in range(N_ROWS):
        st[r * LANES + dst] = st[r * LANES + src]
    for r in range(ring.shape[0] // width):
        ring[r * width + dst] = ring[r * width + src]
    for r in range(e_ring.shape[0] // width):
        e_ring[r * width + dst] = e_ring[r * width + src]
    for f in range(LI_FIELDS):
        li[dst, f] = li[src, f]
    lane_of[dst] = lane_of[src]


@njit(**BATCH_JIT)
def padded(n_a, width):
    """The columns a step computes: the n_a active lanes and padding up to a whole vector
    (LLVM computes the lanes past the last whole vector one by one, its scalar remainder,
    at the single kernel's cost, where a padded vector computes them at once)."""
    return min(width, (n_a + VECTOR - 1) // VECTOR * VECTOR)


@njit(**BATCH_JIT)
def pad_lanes(n_a, width, st, ring, e_ring, li, lane_of):
    """The padding columns n_a..padded(n_a) - 1 become copies of lane 0, so that they
    compute finite numbers (a lane that left may have been out of bounds). Their samples,
    logs and results are nobody's: the lanes' loops over them write st and the rings only."""
    if n_a == 0:
        return
    for c in range(n_a, padded(n_a, width)):
        copy_lane(0, c, width, st, ring, e_ring, li, lane_of)


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
    st, ring, e_ring, li, lane_of, at = start_batch(rk4, coef, n_delay, sampler, trace_stride,
                                                    lyap, renorm, win, trace)
    batch_steps(rk4, dt, n_delay, n_steps, n_steps, lyap, renorm, st, ring, e_ring, li,
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
def lane_template(sampler, trace_stride, n_win, n_trace):
    """A lane's li row at its step 0: its samplers from the grid's schedule (sampler: the
    window's first step, stride, jump and resume), started at the batch's step 0."""
    row = np.zeros(LI_FIELDS, dtype=np.int64)
    row[W_NEXT], row[W_STRIDE], row[W_JUMP], row[W_RESUME] = sampler[0], sampler[1], sampler[2], sampler[3]
    row[W_COUNT], row[T_STRIDE], row[T_COUNT] = n_win, trace_stride, n_trace
    return row


@njit(**BATCH_JIT)
def empty_batch(rk4, width, n_delay, lyap, renorm):
    """A batch of ``width`` columns and no lane yet, at step 0: (st, ring, e_ring, li,
    lane_of, at); fill_lane gives it its lanes."""
    # rk4: (m_x, m_y) at steps n - N..n, rows 2 pos and 2 pos + 1, and the history slot
    # ``size`` after them (rk4_steps); Euler: m_x over (t - tau, t]
    size = ring_size(rk4, n_delay)
    n_ring = 2 * (size + 1) * width if rk4 else size * width
    st, ring, e_ring = skewed_buffers(n_ring, n_ring if lyap else 0)
    li = np.zeros((width, LI_FIELDS), dtype=np.int64)
    lane_of = np.zeros(width, dtype=np.int64)
    at = np.array([0, 0, 0, NEVER, 0, renorm], dtype=np.int64)
    return st, ring, e_ring, li, lane_of, at


@njit(**BATCH_JIT)
def fill_lane(point, c, rk4, n_delay, st, ring, e_ring, li, lane_of, at, template):
    """Point ``point`` (its coefficients c, core.model.coefficients) starts in the first free
    column at the batch's step at[B_N], from eq. 19 as at step 0: its state, its ring
    columns (the history before t = 0: Euler's m_x = delta in every slot, RK4's (delta, 0)
    in every slot, which is what its history slot holds; the tangent's 0) and its
    samplers (template, lane_template) counted from this step.

    Its lane then takes the steps a lane started at step 0 takes, with the same numbers:
    the delay ring is read at the same lags; renormalisations fall on the same lane steps
    if the start is one of the batch's renormalisation steps (a multiple of renorm: the
    caller's to keep), and renormalise_lanes sums the ring in the slots' age order. RK4
    alone reads the history by the step number (rk4_steps: the history slot while
    t + dt - tau <= 0): a lane started later reads its ring instead, whose slots hold
    the same (delta, 0), up to the lane's step N - 1, whose late read is step 0's slot,
    (delta, m_y(0) = delta) where the history has slope 0: the patch sets that slot's
    m_y (and the tangent's e_y) to 0 for that one step (patches). That needs N >= 2 (with N = 1 the
    slot is written in the same step it is read): the caller's to keep."""
    j = at[B_ACTIVE]
    n = at[B_N]
    width = lane_of.shape[0]
    start_lane(j, c, st)
    for r in range(ring.shape[0] // width):
        ring[r * width + j] = c[5] if (not rk4 or r % 2 == 0) else 0.0
    for r in range(e_ring.shape[0] // width):
        e_ring[r * width + j] = 0.0
    for f in range(LI_FIELDS):
        li[j, f] = template[f]
    li[j, OFF] = n
    size = ring_size(rk4, n_delay)
    if rk4 and n > 0 and n_delay > 0:
        li[j, PATCH], li[j, P_STEP], li[j, P_SLOT] = 1, n + n_delay - 1, n % size
    lane_of[j] = point
    at[B_ACTIVE] = j + 1
    at[B_DUE] = min(at[B_DUE], next_due(li, j))


@njit(**BATCH_JIT)
def patches(n, n_a, width, st, ring, e_ring, li, lyap, undo):
    """Undo (``undo``) the history patches due at the batch's step n, or make them (see
    fill_lane); returns the next batch step at which one is due (NEVER: none)."""
    nxt = NEVER
    for j in range(n_a):
        state = li[j, PATCH]
        if state == 0:
            continue
        row = (2 * li[j, P_SLOT] + 1) * width + j  # m_y's (e_y's) row of step 0's slot
        if undo and state == 2 and li[j, P_STEP] + 1 == n:
            ring[row] = st[SV_Y * LANES + j]
            if lyap:
                e_ring[row] = st[SV_EY * LANES + j]
            li[j, PATCH] = state = 0
        elif not undo and state == 1 and li[j, P_STEP] == n:
            st[SV_Y * LANES + j] = ring[row]
            ring[row] = 0.0
            if lyap:
                st[SV_EY * LANES + j] = e_ring[row]
                e_ring[row] = 0.0
            li[j, PATCH] = state = 2
        if state == 1:
            nxt = min(nxt, li[j, P_STEP])
        elif state == 2:
            nxt = min(nxt, li[j, P_STEP] + 1)
    return nxt


@njit(**BATCH_JIT)
def settle_lane(j, n, st, li, win, trace, lane_of, cross):
    """Lane j's records of the state at the batch's step n, as a single kernel makes them
    for the state it stops at: the samples due there and the minima (both idempotent,
    core.methods item 3), and whether they crossed."""
    k = n - li[j, OFF]
    sample_due(j, k, st, li, win, trace, lane_of)
    lowest_lane(st, j, st[S_X * LANES + j], st[S_Y * LANES + j], st[U * LANES + j])
    if cross[lane_of[j]] < 0 and (st[LO_X * LANES + j] < -REALISABLE_TOL
                                  or st[LO_Y * LANES + j] < -REALISABLE_TOL
                                  or st[LO_D * LANES + j] < -REALISABLE_TOL):
        cross[lane_of[j]] = k


@njit(**BATCH_JIT)
def settle_lanes(at, st, li, win, trace, lane_of, cross):
    """settle_lane for every active lane at the batch's step: what a lane's trajectory so
    far holds, for a caller that looks at it between two calls of batch_steps."""
    for j in range(at[B_ACTIVE]):
        settle_lane(j, at[B_N], st, li, win, trace, lane_of, cross)


@njit(**BATCH_JIT)
def retire_lane(j, width, st, ring, e_ring, li, lane_of, at, win, trace, done, lows, cross):
    """Lane j stops at the batch's step: its records there (settle_lane), its steps in done
    and its minima in lows; its column goes to the last active lane (remove_lane)."""
    n = at[B_N]
    settle_lane(j, n, st, li, win, trace, lane_of, cross)
    done[lane_of[j]] = n - li[j, OFF]
    for v in range(3):
        lows[lane_of[j], v] = st[(LO_X + v) * LANES + j]
    at[B_ACTIVE] = remove_lane(j, at[B_ACTIVE], width, st, ring, e_ring, li, lane_of)


@njit(**BATCH_JIT)
def start_batch(rk4, coef, n_delay, sampler, trace_stride, lyap, renorm, win, trace):
    """A batch's whole state at t = 0 (eq. 19 in every lane, one per row of coef): (st,
    ring, e_ring, li, lane_of, at), what batch_steps continues from."""
    n_lanes = coef.shape[0]
    st, ring, e_ring, li, lane_of, at = empty_batch(rk4, n_lanes, n_delay, lyap, renorm)
    template = lane_template(sampler, trace_stride, win.shape[1], trace.shape[1])
    for j in range(n_lanes):
        fill_lane(j, coef[j], rk4, n_delay, st, ring, e_ring, li, lane_of, at, template)
    return st, ring, e_ring, li, lane_of, at


@njit(**BATCH_JIT)
def batch_steps(rk4, dt, n_delay, n_steps, stop, lyap, renorm, st, ring, e_ring, li, lane_of,
                at, win, trace, logs, done, lows, cross):
    """Integrate the batch from its state (start_batch's or empty_batch's arrays, ``at``
    its counters) to the batch's step ``stop`` or until no lane is active, and leave the
    state there: a lane ends at its step n_steps (done = n_steps, lows: the batch's
    outputs, row lane_of) or when it blows up (done = AGAIN), and leaves its column
    (remove_lane). A batch continued from step to step gives each lane what one call gives
    (the kernel contract, core.methods, item 6), but for ``cross``, which is then a chunk
    end no later than one call's (_realisability finds the exact step from either)."""
    width = lane_of.shape[0]
    size = ring_size(rk4, n_delay)
    # the ring rows in the tangent's norm: RK4's N + 1 slots (two rows each), Euler's N,
    # none without delay (core.euler's empty history)
    rows = 2 * size if rk4 else n_delay
    n, pos, n_a = at[B_N], at[B_POS], at[B_ACTIVE]
    i_r, r_next = at[B_I_R], at[B_R_NEXT]
    due = NEVER
    for j in range(n_a):
        due = min(due, next_due(li, j))
    pad_lanes(n_a, width, st, ring, e_ring, li, lane_of)
    while n_a > 0:
        patch_next = patches(n, n_a, width, st, ring, e_ring, li, lyap, True) if rk4 else NEVER
        n_w = padded(n_a, width)
        if lyap and n == r_next:
            if rk4:  # the stale slot (step n - N - 1) must vanish from the norm
                row = 2 * pos * width
                for j in range(n_w):
                    e_ring[row + j] = st[E_X * LANES + j]
                    e_ring[row + width + j] = 0.0
            renormalise_lanes(n_a, n_w, width, st, e_ring, rows, 2 * pos if rk4 else pos,
                              2 if rk4 else 1, dt, logs, lane_of, li, i_r, renorm)
            i_r += 1
            r_next += renorm
        j = 0
        while j < n_a:  # the lanes at their end: the final state, as the single kernels count it
            if li[j, OFF] + n_steps != n:
                j += 1
                continue
            settle_lane(j, n, st, li, win, trace, lane_of, cross)
            done[lane_of[j]] = n_steps
            for v in range(3):
                lows[lane_of[j], v] = st[(LO_X + v) * LANES + j]
            n_a = remove_lane(j, n_a, width, st, ring, e_ring, li, lane_of)
        if n_a == 0 or n >= stop:
            break
        if rk4:
            patch_next = min(patch_next, patches(n, n_a, width, st, ring, e_ring, li, lyap, False))
        end = min(n + MAX_CHUNK, stop, patch_next)
        for j in range(n_a):
            end = min(end, li[j, OFF] + n_steps)
        if lyap:
            end = min(end, r_next)
        n_w = padded(n_a, width)
        if rk4:
            pos, due = rk4_steps(end - n, n, n_a, n_w, width, st, ring, e_ring, pos, size,
                                 n_delay, dt, lyap, due, li, win, trace, lane_of)
        else:
            pos, due = euler_steps(end - n, n, n_a, n_w, width, st, ring, e_ring, pos, size,
                                   n_delay, dt, lyap, due, li, win, trace, lane_of)
        n_a = drop_blown(n_a, width, st, ring, e_ring, li, lane_of, done)
        crossed(n_a, st, li, lane_of, cross, end)
        n = end
    at[B_N], at[B_POS], at[B_ACTIVE], at[B_DUE], at[B_I_R], at[B_R_NEXT] = n, pos, n_a, due, i_r, r_next


@njit(**BATCH_JIT)
def skip_to(n, rk4, n_delay, renorm, at):
    """A batch with no active lane moves to its step n (a multiple of renorm past its step),
    where fill_lane may start lanes: the ring position and the renormalisations' counters
    as if it had stepped there (a renormalisation at n itself counted as done)."""
    at[B_N], at[B_POS] = n, n % ring_size(rk4, n_delay)
    at[B_I_R], at[B_R_NEXT] = n // renorm, n + renorm
    at[B_DUE] = NEVER


def simulate_batch(points: Sequence[Params], s: SolverSettings | None = None,
                   finished: Finished | None = None) -> list[Trajectory]:
    """Integrate every point with the same settings in batched numba calls.

    Returns one Trajectory per point, in order, equal to ``core.solve.simulate(p, s)``.
    Points are grouped by grid (their tau), and each group is integrated LANES points at a
    time (a group of fewer than MIN_LANES by the single kernel); each run's runtime_s is
    its call's wall time shared in proportion to its steps.
    The lanes start from eq. 19's constant history only (core.history): a run with
    another history is computed alone (the queue batches runs of one history).

    ``finished``: a run may stop early. After every chunk of chunk_steps (at least
    CHUNK_T time units) each run still going is shown as its trajectory so far (samples,
    logs and minima up to the chunk's end, ``chunk`` its state there); where
    ``finished`` says True it stops there (steps_done, t_done: where), and its lane takes
    the group's next waiting point (_Lanes). Every run's record is the one of the same
    point in a batch without stops, up to where it stopped, bit for bit.
    """
    s = s or SolverSettings()
    if s.history != "constant":
        raise ValueError(f"the batched kernels start from the constant history only, not "
                         f"{s.history!r}: compute such runs with core.solve.simulate")
    if not method(s.method).batched:  # no lane kernel (core.methods): one run after another
        return [_alone(p, s, finished) for p in points]
    grids = [make_grid(p, s) for p in points]
    groups: dict[Grid, list[int]] = {}
    for i, g in enumerate(grids):
        groups.setdefault(g, []).append(i)
    out: list[Trajectory | None] = [None] * len(points)
    for g, members in groups.items():
        if len(members) < MIN_LANES:
            for i in members:
                out[i] = _alone(points[i], s, finished)
            continue
        # without stops, LANES points at a time (their lanes all end together); with
        # them, the whole group on LANES lanes, a lane taking the next point as one stops
        size = LANES if finished is None or not refills(g, s) else len(members)
        for first in range(0, len(members), size):
            lanes = members[first:first + size]
            runs = _Lanes(g, [points[i] for i in lanes], s).run(finished)
            for i, tr in zip(lanes, runs, strict=True):
                out[i] = tr
    return [tr for tr in out if tr is not None]


#: What a run stopped by simulate_batch_asking keeps beside it (its certificate, say).
E = TypeVar("E")
#: What decides that a run may stop: its trajectory so far (simulate_batch).
Finished = Callable[[Trajectory], bool]
#: A batch with stops asks ``finished`` after chunks of at least this many time units (a
#: whole number of renormalisation intervals: chunk_steps). Each question costs a
#: trajectory view per lane (and whatever ``finished`` does); a chunk of 1e3 time units
#: is 1e6 Euler steps, against which the view's cost (the lane's ring copied once) is
#: nothing, and a lane that stops waits at most that long for its question.
CHUNK_T = 1000.0


def chunk_steps(g: Grid) -> int:
    """Steps between two questions of ``finished``: CHUNK_T rounded up to whole
    renormalisation intervals, so that a lane refilled at a chunk's end starts at a
    renormalisation step (fill_lane)."""
    return g.renorm_steps * max(1, math.ceil(CHUNK_T / (g.renorm_steps * g.dt) - 1e-9))


def refills(g: Grid, s: SolverSettings) -> bool:
    """Whether a lane may take another point after step 0: not RK4 with a delay of one
    step (fill_lane)."""
    return not (s.method == "rk4" and g.n_delay == 1)


def _alone(p: Params, s: SolverSettings, finished: Finished | None) -> Trajectory:
    """One run with the single kernel, asked ``finished`` at the same chunk ends as a lane."""
    if finished is None:
        return simulate(p, s)
    g = make_grid(p, s)
    c = chunk_steps(g)
    tr = simulate(p, s, until=c * g.dt)
    while tr.chunk is not None and not finished(tr):
        tr = simulate(p, s, resume=tr, until=(tr.steps_done + c) * g.dt)
    return tr


#: What a lane's run at one of its chunk ends is asked (simulate_batch_asking): what stops
#: it there (its evidence, kept beside its run), or None: it goes on.
Ask = Callable[[Trajectory], E | None]
#: A grid's chunk ends (simulate_batch_asking): (the chunk's last step, the grid of a run of
#: that length), the last (g.n_steps, g), each twice the one before it.
Ends = Callable[[Params, Grid], list[tuple[int, Grid]]]


#: A run computed by the single kernel instead (simulate_batch_asking): from its start
#: (None), or onward from a lane's run at a chunk end.
Alone = Callable[[Params, Trajectory | None], tuple[Trajectory, E | None]]


def simulate_batch_asking(points: Sequence[Params], s: SolverSettings, ends: Ends, ask: Ask[E],
                          alone: Alone[E]) -> list[tuple[Trajectory, E | None]]:
    """Integrate every point with the same settings in batched numba calls, each run asked
    ``ask`` at the chunk ends of its grid (``ends``) and stopped at the first that answers
    (what answered kept beside the run); a run that never stops is the no-stop batch's run
    to t_end, bit for bit (samples, logs, minima, state) while it stays on the lanes, and
    the single kernel's continuation of it where it goes on ``alone``.

    Unlike simulate_batch's ``finished`` (questions every CHUNK_T, lanes refilled), the
    lanes of a batch all start at step 0 and none is refilled, so that their chunk ends are
    the batch's and each chunk's window (the last ``window`` time units before its end)
    is sampled in every lane by rewriting its sampler between chunks (_Lanes.run_asking).
    A stopped lane's column goes to the last active one: the lanes still going stay dense.
    Groups of fewer than MIN_LANES points, and methods with no lane kernel, go to
    ``alone`` from their start, and so do a batch's last lanes, onward from their chunk
    end, when fewer than MIN_LANES are left (_Lanes.run_asking says why)."""
    if s.history != "constant":
        raise ValueError(f"the batched kernels start from the constant history only, not "
                         f"{s.history!r}: compute such runs with core.solve.simulate")
    out: list[tuple[Trajectory, E | None] | None] = [None] * len(points)
    groups: dict[Grid, list[int]] = {}
    for i, p in enumerate(points):
        groups.setdefault(make_grid(p, s), []).append(i)
    for g, members in groups.items():
        chunks = ends(points[members[0]], g)
        if len(members) < MIN_LANES or not method(s.method).batched or len(chunks) < 2 \
                or not refills(g, s):
            for i in members:
                out[i] = alone(points[i], None)
            continue
        for first in range(0, len(members), LANES):
            lanes = members[first:first + LANES]
            runs = _Lanes(g, [points[i] for i in lanes], s).run_asking(chunks, ask, alone)
            for i, run in zip(lanes, runs, strict=True):
                out[i] = run
    return [run for run in out if run is not None]


def _integrate(g: Grid, points: list[Params], s: SolverSettings) -> list[Trajectory]:
    """One batch without stops: up to LANES points on grid g."""
    return _Lanes(g, points, s).run(None)


class _Lanes:
    """The points of one grid on up to LANES lanes: a lane that ends (its t_end, a stop, a
    blow-up) takes the next waiting point at the next chunk's end, or is padding (pad_lanes)
    when none waits.

    Lanes then run at different model times: each has its samplers and its step 0 (li:
    OFF), which is always one of the batch's renormalisation steps (chunk ends are, and a
    batch with no active lane skips to one: skip_to), so that every lane renormalises at
    its own multiples of renorm_steps, as a lane started at step 0 does (fill_lane says
    what else a later start keeps the same)."""

    def __init__(self, g: Grid, points: list[Params], s: SolverSettings, lanes: int = LANES) -> None:
        self.g, self.points, self.s = g, points, s
        self.rk4 = s.method == "rk4"
        m = len(points)
        # whole vectors (padded): an adaptive sweep's refined levels have a few points per
        # tau (the (k, tau) plane at 100 x 100: batches of 2-13)
        self.width = min(lanes, -(-m // VECTOR) * VECTOR)
        # A lane's samples are rows of 5 values: one stream of writes per lane; trajectories
        # get (5, n) views. Every sample up to a lane's end or blow-up is written
        # (trajectory_of keeps no more), so no NaN fill is needed, and the arrays of an
        # earlier call that nothing refers to any more are written again (core.spare_buffers).
        self.win = sample_array((m, g.n_samples, 5))
        self.trace = sample_array((m, g.n_trace, 5))
        self.n_logs = g.n_steps // g.renorm_steps if s.lyap else 0
        self.logs = np.zeros((m, self.n_logs))
        self.done = np.zeros(m, dtype=np.int64)
        self.lows = np.zeros((m, 3))
        self.cross = np.full(m, -1, dtype=np.int64)
        self.coef = np.stack([coefficients(p) for p in points])
        self.state = empty_batch(self.rk4, self.width, g.n_delay, s.lyap, g.renorm_steps)
        sampler = np.array([g.sample_start, g.win_stride, g.sample_jump, g.win_start], dtype=np.int64)
        self.template = lane_template(sampler, g.trace_stride, g.n_samples, g.n_trace)
        self.waiting = 0  # the next point to start
        self.starts: list[tuple[int, int]] = []  # (point, the batch's step it started at)
        self.stopped: dict[int, Trajectory] = {}  # point -> its run, stopped by ``finished``
        self.t_first: dict[int, float | None] = {}
        self.times: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None

    @property
    def at(self) -> np.ndarray:
        return self.state[5]

    def _outputs(self) -> tuple[np.ndarray, ...]:
        return self.win, self.trace, self.logs, self.done, self.lows, self.cross

    def _fill(self) -> None:
        """Start waiting points in the free columns, at the batch's step (a renormalisation
        step); RK4 with a delay of one step restarts only at step 0 (fill_lane)."""
        at = self.at
        if at[B_N] % self.g.renorm_steps or (at[B_N] > 0 and not refills(self.g, self.s)):
            return
        st, ring, e_ring, li, lane_of, _ = self.state
        while self.waiting < len(self.points) and at[B_ACTIVE] < self.width:
            fill_lane(self.waiting, self.coef[self.waiting], self.rk4, self.g.n_delay, st, ring,
                      e_ring, li, lane_of, at, self.template)
            self.starts.append((self.waiting, int(at[B_N])))
            self.waiting += 1

    def run(self, finished: Finished | None) -> list[Trajectory]:
        """Integrate every point, asking ``finished`` after every chunk (chunk_steps) of
        each lane still going; returns the runs in the points' order."""
        g, s = self.g, self.s
        if len(self.points) > self.width and not refills(g, s):
            raise ValueError(f"RK4 with a delay of one step (tau = dt = {g.dt:g}) restarts no "
                             f"lane after step 0: at most {self.width} points on {self.width} lanes")
        at = self.at
        c = chunk_steps(g) if finished is not None else NEVER
        self._fill()
        t0 = time.perf_counter()
        while True:
            stop = min(int(at[B_N]) + c, NEVER)
            batch_steps(self.rk4, g.dt, g.n_delay, g.n_steps, stop, s.lyap, g.renorm_steps,
                        *self.state, *self._outputs()[:2], *self._outputs()[2:])
            if at[B_ACTIVE] == 0 and self.waiting == len(self.points):
                break
            if at[B_N] < stop:  # every lane ended before the chunk's end: to a step lanes may start at
                r = g.renorm_steps
                skip_to((int(at[B_N]) // r + 1) * r, self.rk4, g.n_delay, r, at)
            elif finished is not None:
                self._ask(finished)
            self._fill()
        runtime = time.perf_counter() - t0
        return self._runs(runtime)

    def run_asking(self, ends: list[tuple[int, Grid]], ask: Ask[E], alone: Alone[E]
                   ) -> list[tuple[Trajectory, E | None]]:
        """Every point from step 0 (no more than the lanes), asked ``ask`` at each chunk end
        of ``ends`` but the last (t_end) with its chunk's trajectory (_chunk_view); a lane
        that answers stops there. Each chunk samples its end window into the window's end
        half (_chunk_sampler), the one before it having moved to the middle half: at t_end
        the halves hold the run's middle and end windows, as a run without stops has them.

        Lanes are padded to whole vectors, so that a few lanes left cost a vector's steps:
        with fewer than MIN_LANES left they go on alone (``alone``, onward from their chunk
        end). Measured at tau = 10, t_end 1e5 (benchmarks/bench_certified_batch.py): 8
        lanes to t_end took 3.2-3.4 s of CPU, one run on the single kernel 1.0 s, so that
        three runs alone cost about what a vector costs.
        Each run's runtime_s is its share of the kernels' time (its steps on the lanes),
        its own questions' and its own steps alone."""
        g = self.g
        st, ring, e_ring, li, lane_of, at = self.state
        assert len(self.points) <= self.width and ends[-1][0] == g.n_steps
        self._fill()
        found: dict[int, E] = {}
        onward: dict[int, Trajectory] = {}  # point -> its run, continued alone
        asked = np.zeros(len(self.points))
        kernel_s = 0.0
        for c, (end, part) in enumerate(ends):
            if c and g.n_mid:  # the previous chunk's window: this chunk's middle window
                for j in range(int(at[B_ACTIVE])):
                    w = self.win[int(lane_of[j])]
                    w[:g.n_mid] = w[g.n_mid:]
            self._chunk_sampler(part, own_middle=c == 0)
            t0 = time.perf_counter()
            batch_steps(self.rk4, g.dt, g.n_delay, g.n_steps, end, self.s.lyap, g.renorm_steps,
                        *self.state, *self._outputs())
            kernel_s += time.perf_counter() - t0
            if at[B_ACTIVE] == 0 or end == g.n_steps:
                break
            settle_lanes(at, st, li, self.win, self.trace, lane_of, self.cross)
            going: list[tuple[int, Trajectory]] = []
            for j in range(int(at[B_ACTIVE]) - 1, -1, -1):  # a lane retired takes the last's column
                i = int(lane_of[j])
                t1 = time.perf_counter()
                tr = self._chunk_view(j, part)
                answer = ask(tr)
                asked[i] += time.perf_counter() - t1
                if answer is not None:
                    self.stopped[i], found[i] = tr, answer
                    retire_lane(j, self.width, st, ring, e_ring, li, lane_of, at, self.win,
                                self.trace, self.done, self.lows, self.cross)
                else:
                    going.append((i, tr))
            if 0 < at[B_ACTIVE] < MIN_LANES:
                for i, tr in going:
                    self.stopped[i] = tr
                    onward[i], answer = alone(tr.params, tr)
                    if answer is not None:
                        found[i] = answer
                break
        runs = self._runs(kernel_s)
        for i, tr in onward.items():
            runs[i] = replace(tr, runtime_s=tr.runtime_s + runs[i].runtime_s)
        return [(replace(tr, runtime_s=tr.runtime_s + asked[i]), found.get(i))
                for i, tr in enumerate(runs)]

    def _chunk_sampler(self, part: Grid, own_middle: bool) -> None:
        """Each active lane's window sampler for the chunk of grid ``part``: its end window
        into the window's end half (rows n_mid on), preceded by its own middle window (the
        first chunk: a run of part's length) where ``own_middle`` and part has one."""
        g = self.g
        li, at = self.state[3], self.at
        n_mid = part.n_mid if own_middle else 0
        assert part.n_win == g.n_win and part.win_stride == g.win_stride and n_mid <= g.n_mid
        for j in range(int(at[B_ACTIVE])):
            li[j, W_NEXT] = part.mid_start if n_mid else part.win_start
            li[j, W_I] = g.n_mid - n_mid
            li[j, W_JUMP] = g.n_mid if n_mid else -1
            li[j, W_RESUME] = part.win_start
            li[j, W_COUNT] = g.n_samples

    def _chunk_view(self, j: int, part: Grid) -> Trajectory:
        """Lane j's run at its chunk's end (the step part.n_steps), as a run of part's length
        would hold it: the chunk's end window and its times, its middle window (the previous
        chunk's, or its own in the first) where part has one, the trace and logs so far, its
        state there (_view)."""
        tr = self._view(j)
        g = self.g
        win = self.win[int(self.state[4][j])].T
        mid_t, mid = np.zeros(0), np.zeros((5, 0))
        if part.n_mid:
            mid_t, mid = window_times(part.mid_start, g.win_stride, part.n_mid, g.dt), win[:, :g.n_mid]
        assert tr.chunk is not None
        return replace(tr, window_t=window_times(part.win_start, g.win_stride, g.n_win, g.dt),
                       window=win[:, g.n_mid:g.n_samples], mid_t=mid_t, mid=mid,
                       final=tr.chunk.carried(tr.params.tau))

    def _ask(self, finished: Finished) -> None:
        """At a chunk's end: each active lane's trajectory so far to ``finished``, and the
        lanes it says are finished stop there (retire_lane)."""
        st, ring, e_ring, li, lane_of, at = self.state
        settle_lanes(at, st, li, self.win, self.trace, lane_of, self.cross)
        for j in range(int(at[B_ACTIVE]) - 1, -1, -1):  # a lane retired takes the last's column
            if at[B_N] == li[j, OFF]:
                continue
            tr = self._view(j)
            if finished(tr):
                self.stopped[int(lane_of[j])] = tr
                retire_lane(j, self.width, st, ring, e_ring, li, lane_of, at, self.win,
                            self.trace, self.done, self.lows, self.cross)

    def _realisability(self, i: int, lows: np.ndarray) -> Realisability:
        """Point i's minima, and its first violation (found once: _realisability)."""
        if i not in self.t_first or (self.t_first[i] is None and self.cross[i] >= 0):
            self.t_first[i] = _realisability(self.points[i], self.s, self.g, lows,
                                             int(self.cross[i])).t_first
        return Realisability(float(lows[0]), float(lows[1]), float(lows[2]), self.t_first[i])

    def _view(self, j: int) -> Trajectory:
        """Lane j's run so far, at the batch's step: its samples, logs and minima, and its
        whole state as a single kernel would hold it (``chunk``: core.chunk_state's layout,
        from which core.solve.simulate could continue it)."""
        g, s = self.g, self.s
        st, ring, e_ring, li, lane_of, at = self.state
        i = int(lane_of[j])
        k = int(at[B_N] - li[j, OFF])
        now = np.empty(cs.NOW_SIZE)
        for r, q in ((M_X, cs.M_X), (M_Y, cs.M_Y), (S_X, cs.S_X), (S_Y, cs.S_Y), (U, cs.U),
                     (E_X, cs.E_X), (E_Y, cs.E_Y), (E_SX, cs.E_SX), (E_SY, cs.E_SY),
                     (E_U, cs.E_U), (LO_X, cs.LO_X), (LO_Y, cs.LO_Y), (LO_D, cs.LO_D)):
            now[q] = st[r * LANES + j]
        real = self._realisability(i, now[cs.LO_X:cs.LO_D + 1])
        m = method(s.method)
        rows, slots = cs.ring_shape(m, g.n_delay)
        counts = np.zeros(cs.COUNTS_SIZE, dtype=np.int64)
        counts[cs.N_AT], counts[cs.POS] = k, k % slots if slots else 0
        counts[cs.NEXT_W], counts[cs.I_W] = li[j, W_NEXT], li[j, W_I]
        counts[cs.NEXT_T], counts[cs.I_T] = li[j, T_NEXT], li[j, T_I]
        counts[cs.I_R] = k // g.renorm_steps
        counts[cs.NEXT_R] = (counts[cs.I_R] + 1) * g.renorm_steps
        counts[cs.FIRST] = -1 if real.t_first is None else g.step_at(real.t_first)
        counts[cs.BLOWN] = -1
        single, e_single = self._ring(ring, j, rows, slots), np.zeros((rows, slots))
        if s.lyap:
            e_single = self._ring(e_ring, j, rows, slots)
        if self.rk4 and slots:
            if li[j, PATCH] == 2:  # step 0's slot (0 here) patched for this step: its own values
                single[1, 0] = st[SV_Y * LANES + j]
                e_single[1, 0] = st[SV_EY * LANES + j] if s.lyap else 1.0
            if not s.lyap:  # the single kernel writes its start tangent (0, 1) regardless
                e_single[1] = 1.0
            if k < slots:  # steps before 0: nothing written there yet
                single[:, k:] = 0.0
                e_single[:, k:] = 0.0
        chunk = ChunkState(s.method, g.dt, g.n_delay, now, counts, single, e_single)
        # trajectory_of's arrays, with the samples the lane's samplers have taken, and the
        # grid's sample times made once (trajectory_of makes them per call: 1.6 MB at the
        # paper's window, per lane and chunk)
        if self.times is None:
            whole = trajectory_of(self.points[i], s, g, g.n_steps, self.win[i].T,
                                  self.trace[i].T, self.logs[i, :self.n_logs], 0.0)
            self.times = (whole.mid_t, whole.window_t, whole.trace_t)
        mid_t, window_t, trace_t = self.times
        win, trace = self.win[i].T, self.trace[i].T
        n_w, n_t = int(li[j, W_I]), int(li[j, T_I])
        n_m = min(n_w, g.n_mid)
        return Trajectory(self.points[i], s, g, k, window_t[:n_w - n_m], win[:, n_m:n_w],
                          trace_t[:n_t], trace[:, :n_t], self.logs[i, :k // g.renorm_steps if s.lyap else 0],
                          0.0, mid_t[:n_m], win[:, :n_m],
                          buffers=(win, trace, self.logs[i, :self.n_logs]), realisability=real,
                          chunk=chunk)

    def _ring(self, ring: np.ndarray, j: int, rows: int, slots: int) -> np.ndarray:
        """Lane j's ring (rows, slots) as the single kernel lays it out: its slot q holds
        the step q modulo slots, which is the batch's slot (OFF + q) modulo the same
        number: the lane's column, turned."""
        column = ring.reshape(-1, self.width)[:rows * slots, j].reshape(slots, rows).T
        return np.roll(column, -int(self.state[3][j, OFF]) % slots if slots else 0, axis=1)

    def _runs(self, runtime: float) -> list[Trajectory]:
        """Every point's run, its runtime_s the batch's in proportion to its steps."""
        g, s = self.g, self.s
        steps = [int(self.stopped[i].steps_done) if i in self.stopped else max(0, int(d))
                 for i, d in enumerate(self.done)]
        total = max(1, sum(steps))
        out = []
        for i, p in enumerate(self.points):
            share = runtime * steps[i] / total
            if i in self.stopped:
                out.append(replace(self.stopped[i], runtime_s=share))
            elif self.done[i] == AGAIN:
                # A lane that blew up is computed again by the single kernel for its exact
                # step (euler_steps), and its run copied into the lane's rows, which no one
                # else holds: the batch's arrays stay alive as long as any lane's views, so a
                # run kept in arrays of its own would hold that lane's samples twice.
                out.append(moved_into(simulate(p, s), (self.win[i].T, self.trace[i].T,
                                                       self.logs[i, :self.n_logs])))
            else:
                out.append(trajectory_of(p, s, g, int(self.done[i]), self.win[i].T,
                                         self.trace[i].T, self.logs[i, :self.n_logs], share,
                                         self._realisability(i, self.lows[i])))
        return out


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
