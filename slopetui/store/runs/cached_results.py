"""The result cache's reads: the finished runs whose result another run may take.

Equal parameters, delta, solver settings and engine give equal results (the model is
deterministic), so a run whose cache key (``slopetui.queue.cache.cache_key``) matches a
finished run's takes that run's result instead of being computed.

Only computed runs serve: an inferred run of an adaptive sweep (``Run.inferred``) is
done and has a cache key, but its regime is a guess from its cell's corners and it has
no measurements, so it must never stand in for a computation.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

from sqlalchemy import bindparam, select
from sqlalchemy.orm import Session

from core.result_fields import RESULT_NAMES
from slopetui.store.database import Database
from slopetui.store.models import Run

_CACHED = (select(Run.id, *(getattr(Run, name) for name in RESULT_NAMES))
           .where(Run.cache_key == bindparam("key"), Run.status == "done",
                  Run.inferred.is_(False))  # an inferred label is not a result
           .order_by(Run.id).limit(1))


def cached_result(db: Database, cache_key: str) -> tuple[int, dict[str, Any]] | None:
    """The id and result fields of the earliest finished, computed run with this cache
    key (a worker asks just before computing: one may have finished since the run was
    queued); None if there is none."""
    with db.read() as conn:
        row = conn.execute(_CACHED, {"key": cache_key}).first()
    if row is None:
        return None
    m = row._mapping
    return m["id"], {name: m[name] for name in RESULT_NAMES}


def finished_results(session: Session, keys: Iterable[str]) -> dict[str, Run]:
    """The earliest finished, computed (not inferred) run for each of the keys that has
    one, read in the caller's transaction."""
    found: dict[str, Run] = {}
    keys = list(set(keys))
    for i in range(0, len(keys), 500):  # stay under SQLite's bound-parameter limit
        rows = session.scalars(select(Run).where(Run.cache_key.in_(keys[i:i + 500]),
                                                 Run.status == "done",
                                                 Run.inferred.is_(False))
                               .order_by(Run.id))
        for run in rows:
            found.setdefault(run.cache_key, run)
    return found


def result_of(run: Run) -> dict[str, Any]:
    """The run's result fields (core.result_fields), by name."""
    return {name: getattr(run, name) for name in RESULT_NAMES}
