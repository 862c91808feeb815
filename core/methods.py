"""The solver methods: one registry, and the contract every integration kernel keeps.

Its own module, without numpy, so that a command line can offer the names as choices
without loading the engine (as core.regimes holds the regime names): the kernels are named
here as "module:function" and imported on first use (``Method.kernel``), because their
modules load numba (~0.3 s), which validating a spec never needs.

The kernel contract
===================

A single-run kernel (core.euler.euler, core.rk4.rk4, core.stiff.stiff) integrates eqs.
6a-6e for one parameter point on the grid of core.solve.make_grid (step dt, delay
tau = n_delay dt exactly, so every delayed read falls on the grid). To add a method:

1. **Signature.** ``kernel(coef, dt, n_delay, lyap, plan, hx, now, counts, ring, e_ring,
   win, trace, logs) -> int``, compiled with ``numba.njit(**core.model.JIT)``:

   - ``coef`` (6,): [a, q, F1, k, d, delta] (core.model.coefficients);
   - ``dt``: the effective step (time units); ``n_delay`` = tau / dt (0: no delay);
   - ``lyap``: co-iterate the tangent for lambda_max (item 5);
   - ``plan`` (int64, PLAN_SIZE): the step to stop at and the samplers' schedule, in
     steps (core.chunk_state.plan_of: END, SAMPLE_START, WIN_STRIDE, WIN_JUMP,
     WIN_RESUME, TRACE_STRIDE, RENORM_STEPS);
   - ``hx`` (2N + 1,): m_x before t = 0 at t = -tau + j dt / 2 (core.history.start);
   - ``now``, ``counts``, ``ring``, ``e_ring``: the run's whole state, read at the start
     and written back at the end (item 6; layout: core.chunk_state);
   - ``win`` (5, n) and ``trace`` (5, n): the samplers' outputs; ``logs``: one log-growth
     of the tangent per renormalisation.

2. **Steps.** It takes the steps n = counts[N_AT] .. plan[END] - 1. Step n advances the
   state at t_n = n dt to t_{n+1}, reading m_x(t_n - tau) (and what else its scheme
   needs over the last delay) from ``ring``, or from ``hx`` while that time is before 0.
   The ring's layout is the kernel's own (its shape: core.chunk_state.ring_shape, from
   ``ring_rows`` and ``ring_extra`` below). Constant coefficients, no allocation.

3. **Records.** Before step n, and once more for the state it stops at, it passes the
   state of step n to core.recording.lowest (the running minima of s_x, s_y, s_x s_y -
   u^2 and the first step one fell below -REALISABLE_TOL) and to core.recording.sample
   for the window sampler (WIN_*) and the trace (every TRACE_STRIDE steps from 0). Both
   are idempotent for the same n, so recording the stopping state twice (at the end of
   a chunk and at the start of the next) changes nothing.

4. **Blow-up.** After each step it tests core.recording.blown_up(m_y, s_y) (and any
   limit of its own: core.stiff's substeps); at the first step n that fails, it sets
   counts[BLOWN] = n, writes back its state and returns n + 1, without recording the
   state beyond the bound. That state is not resumed (core.solve drops it).

5. **Tangent.** With ``lyap`` it co-iterates the exact derivative of its own discrete
   map (the tangent starts at e = (0, 1, 1, 1, 1), its ring at 0) and every
   RENORM_STEPS steps writes core.recording.renormalise's log-growth into logs[i_r].
   Without ``lyap`` the tangent is left alone.

6. **Resumable.** A kernel must be resumable from its state arrays: every quantity that
   lives from one step to the next (the five variables, the tangent, the minima, the
   step, the ring position, the samplers' and the renormalisation's counters, the
   rings) is read from ``now``, ``counts``, ``ring`` and ``e_ring`` at the start and
   written back at the end. A call to step n1 and a second call from there to n2 with
   the same arrays (and the same win, trace, logs) then give what one call to n2 gives,
   bit for bit (tests/unit/test_chunks.py). Nothing else carries over: no local ring,
   no counter that restarts at 0.

7. **Returns** the steps done: plan[END], or n + 1 on blow-up at step n.

8. **Registered** below (METHOD_TABLE): its name, order (core.accuracy's Richardson
   estimate and core.lyapunov_bias), default step, ring rows (core.solve's memory
   limits), and its batched kernel and tangent-spectrum kernel if it has them
   (core.batch, core.tangents), which integrate the same discrete map.

The batched kernels (core.batch) keep the same schedule and records per lane, with a
layout of their own (its module docstring). They start from eq. 19 (start_batch) and are
resumable from their state in the same way (batch_steps), the step of a first
realisability violation aside (a chunk end, which _realisability refines).
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from dataclasses import dataclass
from functools import cache
from typing import Any


@dataclass(frozen=True, slots=True)
class Method:
    """One integration method: what simulate, core.batch, core.accuracy, core.spectrum
    and the command line's --method choices read.

    name       : the --method value.
    order      : the order of its global error in dt (Richardson's p in core.accuracy).
    default_dt : its step when none is given (time units; core.solve.DEFAULT_DT says why).
    kernel_name : its single-run kernel, "module:function" (the contract above; loaded
             by ``kernel()``).
    ring_rows  : rows of its delay ring: 1 (m_x) or 2 (m_x and m_y, for Hermite reads).
    ring_extra : slots of the ring beyond N = tau / dt (RK4 keeps step n - N - 1's).
    batched    : core.batch has a lane kernel for it (core.batch.simulate_batch).
    tangents_name : its N-tangent kernel for the Lyapunov spectrum (core.tangents), or
             None (``tangents()`` loads it).
    """

    name: str
    order: int
    default_dt: float
    kernel_name: str
    ring_rows: int
    ring_extra: int
    batched: bool
    tangents_name: str | None

    def kernel(self) -> Callable[..., Any]:
        """The single-run kernel (imports its module, and numba, on first use)."""
        return _load(self.kernel_name)

    def tangents(self) -> Callable[..., Any] | None:
        """The N-tangent kernel, or None."""
        return _load(self.tangents_name) if self.tangents_name else None


@cache
def _load(name: str) -> Callable[..., Any]:
    module, _, function = name.partition(":")
    return getattr(importlib.import_module(module), function)  # type: ignore[no-any-return]


#: Every method. Euler and RK4 orders are measured (docs/numerics.md: RK4 4.35 -> 4.13
#: from dt = 0.1 to 0.00625); the stiff scheme is linearly implicit Euler, first order
#: (core.stiff).
METHOD_TABLE: tuple[Method, ...] = (
    Method("euler", 1, 1e-3, "core.euler:euler", 1, 0, True, "core.tangents:euler_tangents"),
    Method("rk4", 4, 1e-2, "core.rk4:rk4", 2, 1, True, "core.tangents:rk4_tangents"),
    Method("stiff", 1, 1e-3, "core.stiff:stiff", 1, 0, False, None),
)
#: name -> Method.
REGISTRY: dict[str, Method] = {m.name: m for m in METHOD_TABLE}
#: The names, in the order choices list them.
METHODS: tuple[str, ...] = tuple(REGISTRY)


def method(name: str) -> Method:
    """The registered method ``name`` (KeyError if there is none: settings validate it
    first, core.solve.SolverSettings)."""
    return REGISTRY[name]
