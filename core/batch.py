"""Many parameter points in one numba call: the batched Euler and RK4 kernels.

One trajectory is a chain of dependent floating-point operations: each step waits for the
previous one, so a single run is bound by the latency of that chain (~6 ns per Euler step),
not by the machine's throughput. A batch advances up to ``LANES`` points ("lanes") side by
side, with the state in a structure of arrays: the equations of one step are computed for
all lanes in one loop that LLVM vectorises (AVX: 4 lanes per instruction), and the
independent lanes keep the core's pipelines full.

Lanes differ in everything the single kernels take per run: coefficients, step dt' (core.solve
adjusts dt so that tau = N dt'), delay N (each lane has its own ring buffer), length,
samplers and renormalisation interval. Each slot keeps its own step counter.

* **Delay in blocks.** Reading m_x(t - tau) from a ring buffer is a scalar gather per lane
  and step, which would cost as much as the equations. But the K next delayed values of a
  lane are already in its buffer when K <= N (they were written N steps earlier), so the
  kernel copies K values per lane into a block, runs K vectorised steps, and writes the K
  new values back: the buffer is touched by contiguous copies only.
* **Events** (a tangent renormalisation, the end of a run) are rare: all slots advance
  until the next event of any slot, then the slots that have one handle it.
* **Trace samples are taken inside the blocks.** A lane samples its trace every ~1000
  steps, but 16 lanes of different tau do so at different steps: as events they would
  cut the chunks to ~60 steps. The step loop instead stops at the next step at which any
  slot samples its trace (one comparison per step) and copies that slot's state.
* **Window samples come from the blocks.** The window samples every 10 steps, and lanes
  of different tau sample at different steps: as events they would cut the chunks down
  to a step or two (with the window half of the run: 58 ns per point-step, not 4). A
  block during which a slot samples its window keeps every step's state (planes of
  ``made``), and the samples are copied out of it afterwards (sample_block).
* **Lanes leave without stalling the others.** A lane that has finished or blown up frees
  its slot for the next waiting lane; when none is waiting, the last slot moves into the
  gap, so the vector loop stays dense. Blow-up is found at the exact step (per lane, no
  branch in the vector loop); such a lane leaves at its next event or after at most
  ``MAX_CHUNK`` steps.

Each lane performs the same operations in the same order as the single kernel (core.euler,
core.rk4) on its run: without lambda_max its window, trace and blow-up step equal the single
kernel's bit for bit. With lambda_max, LLVM fuses a few multiply-adds differently (see
euler_block), and a lane agrees with the single kernel to rounding; tests/unit/test_batch.py
checks both, and that regimes and lambda_max agree.
"""

from __future__ import annotations

import time
from collections.abc import Sequence

import numpy as np
from numba import njit, uint64

from core.model import JIT, coefficients, rhs, rhs_tangent
from core.params import Params
from core.recording import blown_up, renormalise
from core.rk4 import hermite_mid
from core.solve import SolverSettings, Trajectory, make_grid, simulate, trajectory_of

#: The engine's numba options, with numpy's error model: Python's would test every
#: division (RK4's dt / 6) for zero, and a possible exception stops LLVM vectorising.
BATCH_JIT = {**JIT, "error_model": "numpy"}
#: Slots of the batch. A compile-time constant, so that LLVM can prove the rows of the
#: state (fl[r * LANES + j]) never overlap and vectorise the step loop without checks.
LANES = 16
#: Steps per delay block (fewer when a lane's delay N is shorter).
BLOCK = 64
#: A lane that blew up stops costing work after at most this many steps.
MAX_CHUNK = 512

# Rows of the flat float state ``fl`` (row r of slot j is fl[r * LANES + j]): the five
# variables, their tangents, the coefficients, the step, and per-slot numbers the vector
# loop needs as floats (the delay N, the step at the start of the block, and the blow-up
# step within the current chunk, 0 if none).
(M_X, M_Y, S_X, S_Y, U, E_X, E_Y, E_SX, E_SY, E_U, CA, CQ, CF1, CK, CD, DELTA, DT,
 N_DELAY_F, STEP_F, BAD) = range(20)
N_FLOAT = 20
# Rows of the flat integer state ``ints``: the lane in the slot, its ring-buffer row, its
# step and its next events.
(LANE, ROW, STEP, N_DELAY, NEXT_W, I_W, NEXT_T, I_T, NEXT_R, I_R) = range(10)
N_INT = 10
# Planes of the flat delay blocks (block[at(plane, i, j)]: step i of the block, slot j):
# m_x, m_y and their tangents, then s_x, s_y, u. ``past`` holds what the block reads from
# the ring buffers (the first 4 planes), ``made`` the state each step started from (all 7:
# what it writes to the ring buffers, and the samples). Two arrays, not one: LLVM does not
# vectorise a loop that reads and writes one array at offsets it cannot compare.
(BX, BY, BEX, BEY, BSX, BSY, BU) = range(7)  # a variable's tangent is two planes after it
N_PAST, N_MADE = 4, 7
# Columns of the per-lane ``plan`` (the core.solve.Grid of each lane).
# The window sampler's columns are those of Grid.sample_start, n_samples, sample_jump and
# win_start (where it resumes after the middle window; core.recording.sample).
(P_N_DELAY, P_N_STEPS, P_WIN_START, P_WIN_STRIDE, P_N_WIN, P_TRACE_STRIDE, P_N_TRACE,
 P_RENORM, P_WIN_JUMP, P_WIN_RESUME) = range(10)
PLAN = ("n_delay", "n_steps", "sample_start", "win_stride", "n_samples", "trace_stride", "n_trace",
        "renorm_steps", "sample_jump", "win_start")


@njit(**BATCH_JIT)
def at(plane, i, j):
    """Index of (plane, step i, slot j) in the flat block: constant strides, like fl's."""
    return (plane * (BLOCK + 1) + i) * LANES + j


@njit(**BATCH_JIT)
def start_lane(j, lane, fl, ints, coef, dt, plan, hist, e_hist, lyap):
    """Put lane ``lane`` in slot j at t = 0: eq. (19), its constant history, its events."""
    delta = coef[lane, 5]
    for r in range(M_X, U + 1):
        fl[r * LANES + j] = delta                             # (19)
    fl[E_X * LANES + j] = 0.0                                 # the tangent, as core.euler
    for r in range(E_Y, E_U + 1):
        fl[r * LANES + j] = 1.0
    for r in range(6):
        fl[(CA + r) * LANES + j] = coef[lane, r]
    fl[DT * LANES + j] = dt[lane]
    row, nd = ints[ROW * LANES + j], plan[lane, P_N_DELAY]
    fl[N_DELAY_F * LANES + j] = nd
    fl[BAD * LANES + j] = 0.0
    hist[row, :, :nd + 1] = delta                             # m_x(t) = delta for t <= 0
    if lyap:
        e_hist[row, :, :nd + 1] = 0.0
    ints[LANE * LANES + j] = lane
    ints[STEP * LANES + j] = 0
    ints[N_DELAY * LANES + j] = nd
    ints[NEXT_W * LANES + j] = plan[lane, P_WIN_START]
    ints[I_W * LANES + j] = 0
    ints[NEXT_T * LANES + j] = 0
    ints[I_T * LANES + j] = 0
    ints[NEXT_R * LANES + j] = plan[lane, P_RENORM]
    ints[I_R * LANES + j] = 0


@njit(**BATCH_JIT)
def move_slot(src, dst, fl, ints):
    """Slot src takes the place of slot dst (whose lane has left); their buffers swap."""
    row = ints[ROW * LANES + dst]
    for r in range(N_FLOAT):
        fl[r * LANES + dst] = fl[r * LANES + src]
    for r in range(N_INT):
        ints[r * LANES + dst] = ints[r * LANES + src]
    ints[ROW * LANES + src] = row


@njit(**BATCH_JIT)
def lane_events(j, fl, ints, plan, e_hist, win, trace, lyap, logs, rows):
    """Slot j's renormalisation at its current step, and at the end of its run the window
    and trace samples of its last state (the blocks sample earlier steps: sample_block,
    take_trace)."""
    lane, n, row = ints[LANE * LANES + j], ints[STEP * LANES + j], ints[ROW * LANES + j]
    if lyap and n == ints[NEXT_R * LANES + j]:
        nd = ints[N_DELAY * LANES + j]
        if rows == 2:  # RK4: the stale slot (step n - N) must vanish from the norm
            pos = n % (nd + 1)
            e_hist[row, 0, pos] = fl[E_X * LANES + j]
            e_hist[row, 1, pos] = 0.0
        i_r = ints[I_R * LANES + j]
        (logs[lane, i_r], fl[E_X * LANES + j], fl[E_Y * LANES + j], fl[E_SX * LANES + j],
         fl[E_SY * LANES + j], fl[E_U * LANES + j]) = renormalise(
            fl[E_X * LANES + j], fl[E_Y * LANES + j], fl[E_SX * LANES + j],
            fl[E_SY * LANES + j], fl[E_U * LANES + j], e_hist[row], nd + rows - 1,
            fl[DT * LANES + j])
        ints[I_R * LANES + j] = i_r + 1
        ints[NEXT_R * LANES + j] += plan[lane, P_RENORM]
    if n == plan[lane, P_N_STEPS]:
        sample_slot(win[lane], plan[lane, P_N_WIN], plan[lane, P_WIN_STRIDE],
                    plan[lane, P_WIN_JUMP], plan[lane, P_WIN_RESUME], NEXT_W, I_W, n, j, fl, ints)
        sample_slot(trace[lane], plan[lane, P_N_TRACE], plan[lane, P_TRACE_STRIDE], -1, 0, NEXT_T,
                    I_T, n, j, fl, ints)


@njit(**BATCH_JIT)
def sample_slot(out, count, stride, jump, resume, next_row, i_row, n, j, fl, ints):
    """One sampler of slot j (its next step and column in rows next_row, i_row of ints):
    if it is due at step n, store the slot's state in out[column] (core.recording.sample,
    with the samples as rows)."""
    i = ints[i_row * LANES + j]
    if ints[next_row * LANES + j] == n and i < count:
        for v in range(5):
            out[i, v] = fl[(M_X + v) * LANES + j]
        ints[i_row * LANES + j] = i + 1
        if i + 1 == jump:
            ints[next_row * LANES + j] = resume
        else:
            ints[next_row * LANES + j] += stride


@njit(**BATCH_JIT)
def steps_to_next_event(n_active, ints, plan, lyap):
    """How many steps every active slot can take before one of them has an event."""
    m = MAX_CHUNK
    for j in range(n_active):
        lane, n = ints[LANE * LANES + j], ints[STEP * LANES + j]
        until = plan[lane, P_N_STEPS]
        if lyap:
            until = min(until, ints[NEXT_R * LANES + j])
        m = min(m, until - n)
    return m


@njit(**BATCH_JIT)
def block_length(m, n_active, ints, rows):
    """Steps of the next delay block: at most BLOCK and m, and short enough that every value
    it reads was written before it (K <= N for Euler, K <= N - 1 for RK4)."""
    k = min(BLOCK, m)
    for j in range(n_active):
        nd = ints[N_DELAY * LANES + j]
        if nd > 0:
            k = min(k, nd - (rows - 1))
    return max(k, 1)


@njit(**BATCH_JIT)
def read_block(k, n_active, fl, ints, flat, e_flat, width, past, lyap, rows):
    """Copy each slot's delayed values for the next k steps from its ring buffer.

    Step s is kept at position s mod N (Euler) or s mod (N + 1) (RK4), as in the single
    kernels. Euler steps n..n+k-1 read steps n-N..n-N+k-1; RK4 reads k + 1 steps from n-N.
    """
    for j in range(n_active):
        nd = ints[N_DELAY * LANES + j]
        if nd == 0:
            continue
        row, size = ints[ROW * LANES + j], nd + rows - 1
        start = (ints[STEP * LANES + j] + rows - 1) % size  # where step n - N is kept
        count = k + rows - 1
        for var in range(rows):  # m_x, and m_y for RK4: planes BX + var and BEX + var
            base = (row * rows + var) * width
            copy_from_ring(flat, base, size, start, count, past, BX + var, j)
            if lyap:
                copy_from_ring(e_flat, base, size, start, count, past, BEX + var, j)
        if rows == 2 and nd == 1:  # tau = dt: RK4's second value is step n, the current state
            past[at(BX, 1, j)], past[at(BY, 1, j)] = fl[M_X * LANES + j], fl[M_Y * LANES + j]
            past[at(BEX, 1, j)], past[at(BEY, 1, j)] = fl[E_X * LANES + j], fl[E_Y * LANES + j]


@njit(**BATCH_JIT)
def copy_from_ring(flat, base, size, start, count, block, plane, j):
    """block[plane, 0..count-1, j] = the ring at flat[base:base + size], from position start,
    wrapping at size.

    Flat arrays and unsigned indices: a slice or reshape per call would cost a reference
    count (~20 ns), and a signed index a wraparound test per element."""
    first = min(count, size - start)
    src, dst = uint64(base + start), uint64(at(plane, 0, j))
    for i in range(first):
        block[dst + uint64(i * LANES)] = flat[src + uint64(i)]
    src = uint64(base)
    for i in range(first, count):
        block[dst + uint64(i * LANES)] = flat[src + uint64(i - first)]


@njit(**BATCH_JIT)
def copy_to_ring(flat, base, size, start, count, block, plane, j):
    """The ring at flat[base:base + size], from position start, wrapping at size =
    block[plane, 0..count-1, j]."""
    first = min(count, size - start)
    src, dst = uint64(at(plane, 0, j)), uint64(base + start)
    for i in range(first):
        flat[dst + uint64(i)] = block[src + uint64(i * LANES)]
    dst = uint64(base)
    for i in range(first, count):
        flat[dst + uint64(i - first)] = block[src + uint64(i * LANES)]


@njit(**BATCH_JIT)
def write_block(k, n_active, ints, flat, e_flat, width, made, lyap, rows):
    """Store the k states the block started its steps from in the ring buffers: Euler's
    step n + i overwrites step n + i - N, as core.euler does."""
    for j in range(n_active):
        nd = ints[N_DELAY * LANES + j]
        if nd == 0 and rows == 1:
            continue
        row, size = ints[ROW * LANES + j], nd + rows - 1
        start = ints[STEP * LANES + j] % size
        for var in range(rows):
            base = (row * rows + var) * width
            copy_to_ring(flat, base, size, start, k, made, BX + var, j)
            if lyap:
                copy_to_ring(e_flat, base, size, start, k, made, BEX + var, j)


@njit(**BATCH_JIT)
def window_due(k, n_active, ints, plan):
    """Whether a slot samples its window during the next k steps."""
    for j in range(n_active):
        lane = ints[LANE * LANES + j]
        if (ints[I_W * LANES + j] < plan[lane, P_N_WIN]
                and ints[NEXT_W * LANES + j] < ints[STEP * LANES + j] + k):
            return True
    return False


@njit(**BATCH_JIT)
def sample_block(k, n_active, ints, plan, made, win):
    """Copy the window samples of the block's k steps out of ``made``: the samples
    core.recording.sample would have taken at steps n..n+k-1 of each slot. A lane that
    blew up in the block also gets the samples after it, which trajectory_of drops (the
    single kernel stopped before them)."""
    for j in range(n_active):
        lane, n = ints[LANE * LANES + j], ints[STEP * LANES + j]
        ints[NEXT_W * LANES + j], ints[I_W * LANES + j] = sample_steps(
            n, n + k, ints[NEXT_W * LANES + j], ints[I_W * LANES + j],
            plan[lane, P_WIN_STRIDE], plan[lane, P_N_WIN], plan[lane, P_WIN_JUMP],
            plan[lane, P_WIN_RESUME], win[lane], made, j)


@njit(**BATCH_JIT)
def sample_steps(n, end, next_n, i, stride, count, jump, resume, out, made, j):
    """One sampler over the block's steps n..end-1 of slot j; return (next_n, i)."""
    while next_n < end and i < count:
        b = next_n - n
        out[i, 0] = made[at(BX, b, j)]
        out[i, 1] = made[at(BY, b, j)]
        out[i, 2] = made[at(BSX, b, j)]
        out[i, 3] = made[at(BSY, b, j)]
        out[i, 4] = made[at(BU, b, j)]
        i += 1
        next_n = resume if i == jump else next_n + stride
    return next_n, i


@njit(**BATCH_JIT)
def next_trace(k, n_active, ints, plan):
    """The first step i < k of the block at which a slot samples its trace, else k."""
    due = k
    for j in range(n_active):
        if ints[I_T * LANES + j] < plan[ints[LANE * LANES + j], P_N_TRACE]:
            due = min(due, ints[NEXT_T * LANES + j] - ints[STEP * LANES + j])
    return due


@njit(**BATCH_JIT)
def take_trace(i, k, n_active, fl, ints, plan, trace):
    """The trace samples due at step i of the block (the state before the step, as
    core.recording.sample); return the next step at which one is due (next_trace)."""
    for j in range(n_active):
        n = ints[STEP * LANES + j] + i
        if ints[NEXT_T * LANES + j] == n:  # before making a view of the lane's trace
            lane = ints[LANE * LANES + j]
            sample_slot(trace[lane], plan[lane, P_N_TRACE], plan[lane, P_TRACE_STRIDE], -1, 0,
                        NEXT_T, I_T, n, j, fl, ints)
    return next_trace(k, n_active, ints, plan)


@njit(**BATCH_JIT)
def mark_blow_up(step, j, fl):
    """Remember the first step of the chunk after which slot j is out of bounds, without a
    branch: BAD stays 0 while the lane is in bounds."""
    first = blown_up(fl[M_Y * LANES + j], fl[S_Y * LANES + j]) & (fl[BAD * LANES + j] == 0.0)
    fl[BAD * LANES + j] += first * (step + 1.0)


@njit(**BATCH_JIT)
def euler_block(k, c, n_active, fl, ints, plan, past, made, trace, lyap, record):
    """Euler steps c..c+k-1 of the chunk for every active slot (core.euler's loop body).

    Loads are unconditional and choices are selects, so that both loops vectorise. The
    tangent has its own loop: one loop with both bodies is too large for LLVM to vectorise
    (3x slower). LLVM then fuses the multiply-adds of the two loops a little differently
    from the single kernel, so with lambda_max a lane agrees with it to rounding, not to the
    bit (tests/unit/test_batch.py); without lambda_max it is bit for bit equal. The five row
    updates of each loop are spelled out: a shared helper looping over the rows stopped
    LLVM vectorising the tangent loop (9.5 ns per point-step against 6.6).
    """
    due = next_trace(k, n_active, ints, plan)
    for i in range(k):
        if lyap:
            for j in range(n_active):
                e_x, e_buf = fl[E_X * LANES + j], past[at(BEX, i, j)]
                e_tau = e_x if fl[N_DELAY_F * LANES + j] == 0.0 else e_buf
                made[at(BEX, i, j)] = e_x
                f = rhs_tangent(fl[M_Y * LANES + j], fl[S_Y * LANES + j], fl[U * LANES + j],
                                e_x, fl[E_Y * LANES + j], fl[E_SX * LANES + j],
                                fl[E_SY * LANES + j], fl[E_U * LANES + j], e_tau,
                                fl[CA * LANES + j], fl[CQ * LANES + j], fl[CF1 * LANES + j],
                                fl[CK * LANES + j])
                dt = fl[DT * LANES + j]
                fl[E_X * LANES + j] = e_x + dt * f[0]
                fl[E_Y * LANES + j] += dt * f[1]
                fl[E_SX * LANES + j] += dt * f[2]
                fl[E_SY * LANES + j] += dt * f[3]
                fl[E_U * LANES + j] += dt * f[4]
        if record:  # the rest of the state, for the window samples (sample_block)
            for j in range(n_active):
                made[at(BY, i, j)] = fl[M_Y * LANES + j]
                made[at(BSX, i, j)] = fl[S_X * LANES + j]
                made[at(BSY, i, j)] = fl[S_Y * LANES + j]
                made[at(BU, i, j)] = fl[U * LANES + j]
        if i == due:
            due = take_trace(i, k, n_active, fl, ints, plan, trace)
        for j in range(n_active):  # (6a-6e)
            m_x, m_x_buf = fl[M_X * LANES + j], past[at(BX, i, j)]
            m_x_tau = m_x if fl[N_DELAY_F * LANES + j] == 0.0 else m_x_buf
            made[at(BX, i, j)] = m_x
            f = rhs(m_x, fl[M_Y * LANES + j], fl[S_X * LANES + j], fl[S_Y * LANES + j],
                    fl[U * LANES + j], m_x_tau, fl[CA * LANES + j], fl[CQ * LANES + j],
                    fl[CF1 * LANES + j], fl[CK * LANES + j], fl[CD * LANES + j])
            dt = fl[DT * LANES + j]
            fl[M_X * LANES + j] = m_x + dt * f[0]
            fl[M_Y * LANES + j] += dt * f[1]
            fl[S_X * LANES + j] += dt * f[2]
            fl[S_Y * LANES + j] += dt * f[3]
            fl[U * LANES + j] += dt * f[4]
            mark_blow_up(c + i, j, fl)


@njit(**BATCH_JIT)
def rk4_block(k, c, n_active, fl, ints, plan, past, made, trace, lyap):
    """RK4 steps c..c+k-1 of the chunk for every active slot (core.rk4's loop body)."""
    due = next_trace(k, n_active, ints, plan)
    for i in range(k):
        if i == due:
            due = take_trace(i, k, n_active, fl, ints, plan, trace)
        for j in range(n_active):
            rk4_lane(i, j, fl, past, made, lyap)
            mark_blow_up(c + i, j, fl)


@njit(inline="always", **BATCH_JIT)
def rk4_lane(i, j, fl, past, made, lyap):
    """Step i of the block for slot j and its tangent: the arithmetic of core.rk4.rk4."""
    a, q, f1 = fl[CA * LANES + j], fl[CQ * LANES + j], fl[CF1 * LANES + j]
    k, d, dt = fl[CK * LANES + j], fl[CD * LANES + j], fl[DT * LANES + j]
    h = 0.5 * dt
    nd = fl[N_DELAY_F * LANES + j]
    no_delay = nd == 0.0
    m_x, m_y, s_x = fl[M_X * LANES + j], fl[M_Y * LANES + j], fl[S_X * LANES + j]
    s_y, u = fl[S_Y * LANES + j], fl[U * LANES + j]
    made[at(BX, i, j)], made[at(BY, i, j)] = m_x, m_y
    made[at(BSX, i, j)], made[at(BSY, i, j)], made[at(BU, i, j)] = s_x, s_y, u
    # t_n + dt - tau <= 0: the delayed values are the history delta (tangent 0)
    history = fl[STEP_F * LANES + j] + i < nd
    delta = fl[DELTA * LANES + j]
    b0, b1 = past[at(BX, i, j)], past[at(BX, i + 1, j)]  # unconditional loads: selects
    bh = hermite_mid(b0, b1, past[at(BY, i, j)], past[at(BY, i + 1, j)], dt)
    x0 = delta if history else b0
    x1 = delta if history else b1
    xh = delta if history else bh
    k1 = rhs(m_x, m_y, s_x, s_y, u, m_x if no_delay else x0, a, q, f1, k, d)
    x2, y2, sx2, sy2, u2 = m_x + h * k1[0], m_y + h * k1[1], s_x + h * k1[2], s_y + h * k1[3], u + h * k1[4]
    k2 = rhs(x2, y2, sx2, sy2, u2, x2 if no_delay else xh, a, q, f1, k, d)
    x3, y3, sx3, sy3, u3 = m_x + h * k2[0], m_y + h * k2[1], s_x + h * k2[2], s_y + h * k2[3], u + h * k2[4]
    k3 = rhs(x3, y3, sx3, sy3, u3, x3 if no_delay else xh, a, q, f1, k, d)
    x4, y4, sx4, sy4, u4 = m_x + dt * k3[0], m_y + dt * k3[1], s_x + dt * k3[2], s_y + dt * k3[3], u + dt * k3[4]
    k4 = rhs(x4, y4, sx4, sy4, u4, x4 if no_delay else x1, a, q, f1, k, d)
    w = dt / 6.0
    if lyap:
        e_x, e_y, e_sx = fl[E_X * LANES + j], fl[E_Y * LANES + j], fl[E_SX * LANES + j]
        e_sy, e_u = fl[E_SY * LANES + j], fl[E_U * LANES + j]
        made[at(BEX, i, j)], made[at(BEY, i, j)] = e_x, e_y
        c0, c1 = past[at(BEX, i, j)], past[at(BEX, i + 1, j)]
        ch = hermite_mid(c0, c1, past[at(BEY, i, j)], past[at(BEY, i + 1, j)], dt)
        ex0 = 0.0 if history else c0
        ex1 = 0.0 if history else c1
        exh = 0.0 if history else ch
        t1 = rhs_tangent(m_y, s_y, u, e_x, e_y, e_sx, e_sy, e_u, e_x if no_delay else ex0, a, q, f1, k)
        g = (e_x + h * t1[0], e_y + h * t1[1], e_sx + h * t1[2], e_sy + h * t1[3], e_u + h * t1[4])
        t2 = rhs_tangent(y2, sy2, u2, g[0], g[1], g[2], g[3], g[4], g[0] if no_delay else exh, a, q, f1, k)
        g = (e_x + h * t2[0], e_y + h * t2[1], e_sx + h * t2[2], e_sy + h * t2[3], e_u + h * t2[4])
        t3 = rhs_tangent(y3, sy3, u3, g[0], g[1], g[2], g[3], g[4], g[0] if no_delay else exh, a, q, f1, k)
        g = (e_x + dt * t3[0], e_y + dt * t3[1], e_sx + dt * t3[2], e_sy + dt * t3[3], e_u + dt * t3[4])
        t4 = rhs_tangent(y4, sy4, u4, g[0], g[1], g[2], g[3], g[4], g[0] if no_delay else ex1, a, q, f1, k)
        fl[E_X * LANES + j] = e_x + w * (t1[0] + 2.0 * (t2[0] + t3[0]) + t4[0])
        fl[E_Y * LANES + j] = e_y + w * (t1[1] + 2.0 * (t2[1] + t3[1]) + t4[1])
        fl[E_SX * LANES + j] = e_sx + w * (t1[2] + 2.0 * (t2[2] + t3[2]) + t4[2])
        fl[E_SY * LANES + j] = e_sy + w * (t1[3] + 2.0 * (t2[3] + t3[3]) + t4[3])
        fl[E_U * LANES + j] = e_u + w * (t1[4] + 2.0 * (t2[4] + t3[4]) + t4[4])
    fl[M_X * LANES + j] = m_x + w * (k1[0] + 2.0 * (k2[0] + k3[0]) + k4[0])
    fl[M_Y * LANES + j] = m_y + w * (k1[1] + 2.0 * (k2[1] + k3[1]) + k4[1])
    fl[S_X * LANES + j] = s_x + w * (k1[2] + 2.0 * (k2[2] + k3[2]) + k4[2])
    fl[S_Y * LANES + j] = s_y + w * (k1[3] + 2.0 * (k2[3] + k3[3]) + k4[3])
    fl[U * LANES + j] = u + w * (k1[4] + 2.0 * (k2[4] + k3[4]) + k4[4])


@njit(**BATCH_JIT)
def advance(m, n_active, fl, ints, plan, flat, e_flat, width, past, made, win, trace, lyap,
            rows):
    """m steps of every active slot, in delay blocks, and their samples."""
    c = 0
    while c < m:
        k = block_length(m - c, n_active, ints, rows)
        read_block(k, n_active, fl, ints, flat, e_flat, width, past, lyap, rows)
        for j in range(n_active):
            fl[STEP_F * LANES + j] = ints[STEP * LANES + j]
        record = window_due(k, n_active, ints, plan)
        if rows == 1:
            euler_block(k, c, n_active, fl, ints, plan, past, made, trace, lyap, record)
        else:  # RK4 keeps the whole state in made at every step (rk4_lane)
            rk4_block(k, c, n_active, fl, ints, plan, past, made, trace, lyap)
        write_block(k, n_active, ints, flat, e_flat, width, made, lyap, rows)
        if record:
            sample_block(k, n_active, ints, plan, made, win)
        for j in range(n_active):
            ints[STEP * LANES + j] += k
        c += k


@njit(**BATCH_JIT)
def batch(rows, coef, dt, plan, hist, e_hist, win, trace, lyap, logs, done):
    """Integrate every lane (row of coef/dt/plan) to its end or blow-up; done[lane] gets
    its number of steps, as the single kernels return. rows 1: Euler, 2: RK4 (the number
    of buffered variables, m_x or m_x and m_y).

    LANES slots advance together; a lane that ends frees its slot for the next lane, and
    when none is left the last slot moves into the gap, so the loops stay dense.
    """
    n_lanes = coef.shape[0]
    fl = np.zeros(N_FLOAT * LANES)
    ints = np.zeros(N_INT * LANES, dtype=np.int64)
    past = np.zeros(N_PAST * (BLOCK + 1) * LANES)
    made = np.zeros(N_MADE * (BLOCK + 1) * LANES)
    flat, e_flat, width = hist.reshape(-1), e_hist.reshape(-1), hist.shape[2]  # C order
    n_active = min(LANES, n_lanes)
    for j in range(n_active):
        ints[ROW * LANES + j] = j
        start_lane(j, j, fl, ints, coef, dt, plan, hist, e_hist, lyap)
    waiting = n_active  # the next lane to start
    while n_active > 0:
        j = 0
        while j < n_active:
            lane, n = ints[LANE * LANES + j], ints[STEP * LANES + j]
            if fl[BAD * LANES + j] == 0.0:
                lane_events(j, fl, ints, plan, e_hist, win, trace, lyap, logs, rows)
                if n < plan[lane, P_N_STEPS]:
                    j += 1
                    continue
                done[lane] = n
            else:
                done[lane] = int(fl[BAD * LANES + j])
            if waiting < n_lanes:
                start_lane(j, waiting, fl, ints, coef, dt, plan, hist, e_hist, lyap)
                waiting += 1
            else:
                n_active -= 1
                move_slot(n_active, j, fl, ints)
        if n_active == 0:
            break
        m = steps_to_next_event(n_active, ints, plan, lyap)
        for j in range(n_active):  # BAD counts steps from the start of this chunk
            fl[BAD * LANES + j] = 0.0
        advance(m, n_active, fl, ints, plan, flat, e_flat, width, past, made, win, trace, lyap,
                rows)
        for j in range(n_active):
            if fl[BAD * LANES + j] != 0.0:  # as a step count since the lane's start
                fl[BAD * LANES + j] += ints[STEP * LANES + j] - m


def simulate_batch(points: Sequence[Params], s: SolverSettings | None = None) -> list[Trajectory]:
    """Integrate every point with the same settings in batched numba calls.

    Returns one Trajectory per point, in order, equal to ``core.solve.simulate(p, s)``.
    Each one's runtime_s is the batch's wall time shared in proportion to its steps.
    The lanes start from eq. 19's constant history only (core.history): a run with
    another history is computed alone (the queue batches runs of one history).
    """
    s = s or SolverSettings()
    if s.history != "constant":
        raise ValueError(f"the batched kernels start from the constant history only, not "
                         f"{s.history!r}: compute such runs with core.solve.simulate")
    if not points:
        return []
    if s.method == "stiff":  # no batched kernel (core.stiff): one run after another
        return [simulate(p, s) for p in points]
    grids = [make_grid(p, s) for p in points]
    n_lanes = len(points)
    plan = np.array([[getattr(g, name) for name in PLAN] for g in grids], dtype=np.int64)
    rows = 1 if s.method == "euler" else 2  # RK4 keeps (m_x, m_y) at N + 1 steps
    width = int(plan[:, P_N_DELAY].max()) + 1
    slots = min(LANES, n_lanes)
    hist = np.zeros((slots, rows, width))
    e_hist = np.zeros((slots, rows, width if s.lyap else 0))
    # A lane's samples are rows of 5 values: one stream of writes per lane, where a (5, n)
    # array per lane makes 5 (with the window half of the run, 5.4 ns per point-step
    # against 4.9). Trajectories get (5, n) views. Every sample up to a lane's end or
    # blow-up is written (trajectory_of keeps no more), so no NaN fill is needed.
    win = np.empty((n_lanes, int(plan[:, P_N_WIN].max()), 5))
    trace = np.empty((n_lanes, int(plan[:, P_N_TRACE].max()), 5))  # as win
    n_logs = plan[:, P_N_STEPS] // plan[:, P_RENORM]
    logs = np.zeros((n_lanes, int(n_logs.max()) if s.lyap else 0))
    done = np.zeros(n_lanes, dtype=np.int64)
    t0 = time.perf_counter()
    batch(rows, np.stack([coefficients(p) for p in points]), np.array([g.dt for g in grids]),
          plan, hist, e_hist, win, trace, s.lyap, logs, done)
    runtime = time.perf_counter() - t0
    share = done / max(1, int(done.sum()))
    return [trajectory_of(p, s, g, int(done[j]), win[j, :g.n_samples].T, trace[j, :g.n_trace].T,
                          logs[j, :n_logs[j] if s.lyap else 0], runtime * share[j])
            for j, (p, g) in enumerate(zip(points, grids, strict=True))]
