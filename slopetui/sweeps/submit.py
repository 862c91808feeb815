"""Turn a validated spec into a sweep and its queued runs, in one transaction.

An adaptive spec queues only its coarse lattice (level 0); ``slopetui.sweeps.adaptive``
queues the next levels as the workers finish each one. Its ``sweeps.n_runs`` is the
final lattice's size: computed and inferred runs fill the lattice when it is refined.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from core.jit_cache import source_digest
from core.params import ParameterError
from core.solve import make_grid
from slopetui.store.database import Database
from slopetui.store.runs.initial_states import save_state
from slopetui.store.sweeps.writes import insert_sweep
from slopetui.sweeps.adaptive import advance
from slopetui.sweeps.carried import RUN_PREFIX, final_state_of, parse_history
from slopetui.sweeps.refinement import coarse_points
from slopetui.sweeps.run_rows import run_rows
from slopetui.sweeps.spec import SpecError, SweepSpec

__all__ = ["Submitted", "resolve_histories", "run_rows", "submit"]


def resolve_histories(db: Database, spec: SweepSpec) -> SweepSpec:
    """The spec with every history run:ID of its initial conditions replaced by the name
    of that run's final state, which is recomputed and kept (slopetui.store
    .initial_states). The state is one delay of one run: every run of the sweep must
    have its tau and step. Raises SpecError naming the condition otherwise."""
    conditions = []
    for i, c in enumerate(spec.initial):
        if c.history is not None and c.history.startswith(RUN_PREFIX):
            where = f"initial[{i}].history"
            _, run_id = parse_history(c.history)
            assert run_id is not None
            try:
                state = final_state_of(db, run_id)
            except ParameterError as exc:
                raise SpecError(where, str(exc)) from None
            for _, _, p in spec.points([(0, 0), (spec.x.num - 1, (spec.y.num - 1) if spec.y else 0)]):
                dt = make_grid(p, spec.solver).dt
                if not (math.isclose(p.tau, state.tau, rel_tol=1e-12)
                        and math.isclose(dt, state.dt, rel_tol=1e-9)):
                    raise SpecError(where, f"run {run_id} has tau = {state.tau:g} and step "
                                           f"{state.dt:g}; this sweep's runs have tau = "
                                           f"{p.tau:g}, step {dt:g}: its final state is one "
                                           "delay long and fits only runs with its tau and step")
            save_state(db, state.name, state.to_bytes(), state.tau, state.dt, run_id)
            c = replace(c, history=state.name)
        conditions.append(c)
    return replace(spec, initial=tuple(conditions))


@dataclass(frozen=True)
class Submitted:
    sweep_id: int
    n_runs: int    # runs inserted now (an adaptive sweep: its coarse lattice)
    n_cached: int  # of them, runs that took the result of an earlier identical run
    #: Points of the (final) lattice: n_runs, or more for an adaptive sweep.
    n_points: int = 0
    adaptive_levels: int | None = None


def submit(db: Database, spec: SweepSpec) -> Submitted:
    """Insert the sweep and its runs; runs already computed take their earlier result.
    An initial condition whose history is run:ID starts from that run's final state,
    recomputed and kept in the store first (resolve_histories)."""
    spec = resolve_histories(db, spec)
    levels = spec.adaptive_levels
    engine = source_digest()
    if levels is None:
        rows = run_rows(spec, engine)
    else:
        assert spec.y is not None  # parse_spec allows [adaptive] on 2-D sweeps only
        rows = run_rows(spec, engine, coarse_points(spec.x.num, spec.y.num, levels))
        for row in rows:
            row["level"] = 0
    sweep_id, n_cached = insert_sweep(
        db, name=spec.name, spec=spec.to_dict(), x_param=spec.x.param,
        y_param=spec.y.param if spec.y else None, n_runs=spec.n_runs, adaptive_levels=levels,
        rows=rows)
    if levels is not None:
        advance(db, sweep_id)  # the whole coarse level may have come from the cache
    return Submitted(sweep_id, len(rows), n_cached, spec.n_runs, levels)
