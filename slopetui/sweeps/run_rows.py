"""Rows of the runs table for a sweep's lattice points, with their cache keys: what
submission and adaptive refinement share (the store inserts them,
``slopetui.store.sweep_rows.insert_runs``)."""

from __future__ import annotations

from collections.abc import Iterable

from core import PARAM_NAMES
from slopetui.queue.cache import cache_key
from slopetui.sweeps.spec import SweepSpec

Row = dict[str, object]


def run_rows(spec: SweepSpec, engine: str,
             points: Iterable[tuple[int, int]] | None = None) -> list[Row]:
    """The input columns of a run for every lattice point (default) or for ``points``."""
    s = spec.solver
    rows = []
    for ix, iy, p in spec.points(points):
        row: Row = {n: getattr(p, n) for n in PARAM_NAMES}
        row.update(ix=ix, iy=iy, method=s.method, dt=s.dt, t_end=s.t_end, window=s.window,
                   lyap=s.lyap, engine=engine)
        row["cache_key"] = cache_key(row)
        rows.append(row)
    return rows

