"""The live workers of a store, read from its workers table, as plain data.

The queue's own view of who is working (the pool finds its workers here, and ``status``,
``workers`` and the TUI list them); ``slopetui.sweeps.progress`` re-exports both names.
"""

from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime, timedelta

from sqlalchemy import select

from slopetui.queue.defaults import LEASE_S
from slopetui.store.database import Database
from slopetui.store.models import Worker


@dataclass(frozen=True)
class WorkerInfo:
    id: str
    host: str
    pid: int
    started_at: datetime
    heartbeat_age_s: float
    run_id: int | None
    jobs_done: int


def live_workers(db: Database) -> list[WorkerInfo]:
    """Workers that have not stopped and sent a heartbeat within the lease."""
    with db.sessions() as s:
        now = db.now(s)
        rows = s.scalars(select(Worker).where(Worker.stopped_at.is_(None),
                                              Worker.heartbeat_at >= now - timedelta(seconds=LEASE_S))
                         .order_by(Worker.started_at))
        return [WorkerInfo(w.id, w.host, w.pid, w.started_at,
                           (now - w.heartbeat_at).total_seconds(), w.run_id, w.jobs_done)
                for w in rows]
