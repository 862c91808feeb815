"""The live workers of a store, read from its workers table, as plain data.

The queue's own view of who is working (the pool finds its workers here, and ``status``,
``workers`` and the TUI list them); ``slopetui.sweeps.progress`` re-exports both names.
"""

from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime

from slopetui.queue.defaults import LEASE_S
from slopetui.store.database import Database
from slopetui.store.workers import live_worker_rows


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
    now, rows = live_worker_rows(db, LEASE_S)
    return [WorkerInfo(w.id, w.host, w.pid, w.started_at,
                       (now - w.heartbeat_at).total_seconds(), w.run_id, w.jobs_done)
            for w in rows]
