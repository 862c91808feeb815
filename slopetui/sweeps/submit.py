"""Turn a validated spec into a sweep and its queued runs, in one transaction.

An adaptive spec queues only its coarse lattice (level 0); ``slopetui.sweeps.adaptive``
queues the next levels as the workers finish each one. Its ``sweeps.n_runs`` is the
final lattice's size: computed and inferred runs fill the lattice when it is refined.
"""

from __future__ import annotations

from dataclasses import dataclass

from core.jit_cache import source_digest
from slopetui.store.database import Database
from slopetui.store.sweep_rows import insert_sweep
from slopetui.sweeps.adaptive import advance
from slopetui.sweeps.refinement import coarse_points
from slopetui.sweeps.run_rows import run_rows
from slopetui.sweeps.spec import SweepSpec

__all__ = ["Submitted", "run_rows", "submit"]


@dataclass(frozen=True)
class Submitted:
    sweep_id: int
    n_runs: int    # runs inserted now (an adaptive sweep: its coarse lattice)
    n_cached: int  # of them, runs that took the result of an earlier identical run
    #: Points of the (final) lattice: n_runs, or more for an adaptive sweep.
    n_points: int = 0
    adaptive_levels: int | None = None


def submit(db: Database, spec: SweepSpec) -> Submitted:
    """Insert the sweep and its runs; runs already computed take their earlier result."""
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
