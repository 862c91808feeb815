"""The writes of a sweep's rows: a new sweep with its runs (the cache answering the runs it
can), and pause, resume and cancel.

``slopetui.sweeps`` decides what the rows hold (``sweeps.run_rows``: the lattice's points
and their cache keys) and what the actions mean to the user (``sweeps.control``).
"""

from __future__ import annotations

from typing import Any

from sqlalchemy import insert, update
from sqlalchemy.orm import Session

from slopetui.store.cached_results import finished_results, result_of
from slopetui.store.database import Database, rows_changed
from slopetui.store.models import Run, Sweep

#: A run's columns by name, as ``insert(Run)`` takes them.
RunRow = dict[str, object]


def insert_runs(s: Session, sweep_id: int, rows: list[RunRow]) -> int:
    """Insert the rows into the sweep, queued, or done with the result of an earlier
    computed run with the same cache key, in the caller's transaction. The rows are
    completed in place (sweep_id, status, and a cached run's result and cached_from).
    Returns how many took a cached result."""
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


def insert_sweep(db: Database, *, name: str, spec: dict[str, Any], x_param: str,
                 y_param: str | None, n_runs: int, adaptive_levels: int | None,
                 rows: list[RunRow]) -> tuple[int, int]:
    """Insert a sweep and its runs (see insert_runs) in one transaction; an adaptive sweep
    (``adaptive_levels`` set) starts at its level 0. Returns (the sweep's id, how many
    runs took a cached result)."""
    with db.transaction() as s:
        sweep = Sweep(name=name, spec=spec, x_param=x_param, y_param=y_param, n_runs=n_runs,
                      adaptive_levels=adaptive_levels,
                      level=None if adaptive_levels is None else 0)
        s.add(sweep)
        s.flush()
        n_cached = insert_runs(s, sweep.id, rows)
    return sweep.id, n_cached


def set_sweep_status(db: Database, sweep_id: int, status: str,
                     allowed_from: tuple[str, ...]) -> str | None:
    """Set the sweep's status if it is one of ``allowed_from`` (else leave it); returns the
    status it has now, or None if there is no such sweep."""
    with db.transaction() as s:
        sweep = s.get(Sweep, sweep_id)
        if sweep is None:
            return None
        if sweep.status in allowed_from:
            sweep.status = status
        return sweep.status


def cancel_sweep(db: Database, sweep_id: int) -> int | None:
    """Mark the sweep cancelled and its queued runs too (running ones finish), in one
    transaction; returns how many runs it cancelled, or None if there is no such sweep."""
    with db.transaction() as s:
        sweep = s.get(Sweep, sweep_id)
        if sweep is None:
            return None
        sweep.status = "cancelled"
        return rows_changed(s.execute(update(Run).where(Run.sweep_id == sweep_id,
                                                        Run.status == "queued")
                                      .values(status="cancelled")))
