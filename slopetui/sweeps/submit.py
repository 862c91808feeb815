"""Turn a validated spec into a sweep and its queued runs, in one transaction."""

from __future__ import annotations

from dataclasses import dataclass

from sqlalchemy import insert

from core import PARAM_NAMES
from core.jit_cache import source_digest
from slopetui.queue.cache import cache_key, finished_results, result_of
from slopetui.store.database import Database
from slopetui.store.models import Run, Sweep
from slopetui.sweeps.spec import SweepSpec


@dataclass(frozen=True)
class Submitted:
    sweep_id: int
    n_runs: int
    n_cached: int  # runs that took the result of an earlier identical run


def run_rows(spec: SweepSpec, engine: str) -> list[dict[str, object]]:
    s = spec.solver
    rows = []
    for ix, iy, p in spec.points():
        row: dict[str, object] = {n: getattr(p, n) for n in PARAM_NAMES}
        row.update(ix=ix, iy=iy, method=s.method, dt=s.dt, t_end=s.t_end, window=s.window,
                   lyap=s.lyap, engine=engine)
        row["cache_key"] = cache_key(row)
        rows.append(row)
    return rows


def submit(db: Database, spec: SweepSpec) -> Submitted:
    """Insert the sweep and its runs; runs already computed take their earlier result."""
    rows = run_rows(spec, source_digest())
    with db.transaction() as s:
        sweep = Sweep(name=spec.name, spec=spec.to_dict(), x_param=spec.x.param,
                      y_param=spec.y.param if spec.y else None, n_runs=len(rows))
        s.add(sweep)
        s.flush()
        cached = finished_results(s, (r["cache_key"] for r in rows))
        for row in rows:
            row["sweep_id"] = sweep.id
            hit = cached.get(row["cache_key"])  # type: ignore[arg-type]
            if hit is not None:
                row.update(result_of(hit), status="done", cached_from=hit.id)
            else:
                row["status"] = "queued"
        # Two bulk inserts, one per column set: executemany needs uniform rows.
        for group in ([r for r in rows if r["status"] == "done"],
                      [r for r in rows if r["status"] == "queued"]):
            if group:
                s.execute(insert(Run), group)
        n_cached = sum(r["status"] == "done" for r in rows)
    return Submitted(sweep.id, len(rows), n_cached)
