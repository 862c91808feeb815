"""Rows of the runs table for a sweep's lattice points, with their cache keys: what
submission and adaptive refinement share (the store inserts them,
``slopetui.store.sweeps.writes.insert_runs``)."""

from __future__ import annotations

from collections.abc import Iterable

from core.params import PARAM_NAMES
from slopetui.queue.cache import cache_key
from slopetui.sweeps.spec import SweepSpec

Row = dict[str, object]


def run_rows(spec: SweepSpec, engine: str,
             points: Iterable[tuple[int, int]] | None = None) -> list[Row]:
    """The input columns of a run for every lattice point (default) or for ``points``,
    one per initial condition (spec.conditions: their delta and history; a history
    run:ID must have been resolved to its state's name by submission)."""
    s = spec.solver
    rows = []
    lattice = list(spec.points(points))
    for ic, (delta, history) in enumerate(spec.conditions):
        for ix, iy, p in lattice:
            row: Row = {n: getattr(p, n) for n in PARAM_NAMES}
            row.update(ix=ix, iy=iy, method=s.method, dt=s.dt, t_end=s.t_end, window=s.window,
                       lyap=s.lyap, stop=s.stop, engine=engine, delta=delta, history=history,
                       ic=ic)
            row["cache_key"] = cache_key(row)
            rows.append(row)
    return rows

