"""Rows of the runs table for a sweep's lattice points, and their insertion with the
cache: what submission and adaptive refinement share."""

from __future__ import annotations

from collections.abc import Iterable

from sqlalchemy import insert
from sqlalchemy.orm import Session

from core import PARAM_NAMES
from slopetui.queue.cache import cache_key, finished_results, result_of
from slopetui.store.models import Run
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


def insert_runs(s: Session, sweep_id: int, rows: list[Row]) -> int:
    """Insert the rows into the sweep, queued, or done with the result of an earlier
    computed run with the same cache key. Returns how many took a cached result."""
    cached = finished_results(s, (r["cache_key"] for r in rows))  # type: ignore[misc]
    for row in rows:
        row["sweep_id"] = sweep_id
        hit = cached.get(str(row["cache_key"]))
        if hit is not None:
            row.update(result_of(hit), status="done", cached_from=hit.id)
        else:
            row["status"] = "queued"
    done = [r for r in rows if r["status"] == "done"]
    # Two bulk inserts, one per column set: executemany needs uniform rows.
    for group in (done, [r for r in rows if r["status"] == "queued"]):
        if group:
            s.execute(insert(Run), group)
    return len(done)
