"""The workers table: a worker process registers on start, unregisters on exit, and the
live ones are read back (the pool, ``status``, ``workers`` and the application list them,
see ``slopetui.queue.workers_table``). Heartbeats are the lease's
(``slopetui.store.jobs.leases.heartbeat``): they extend the worker's leases of every kind too.
"""

from __future__ import annotations

from datetime import datetime, timedelta

from sqlalchemy import select

from slopetui.store.database import Database
from slopetui.store.db_time import db_now
from slopetui.store.models import Worker


def register_worker(db: Database, worker_id: str, host: str, pid: int) -> None:
    """Add the worker's row, or start a stopped one again (a pid reused on the same host:
    the worker id is host and pid)."""
    with db.transaction() as s:
        worker = s.get(Worker, worker_id)
        if worker is None:
            s.add(Worker(id=worker_id, host=host, pid=pid))
        else:  # a pid reused on the same host
            worker.stopped_at, worker.run_id, worker.jobs_done = None, None, 0
            worker.started_at = worker.heartbeat_at = db_now()


def unregister_worker(db: Database, worker_id: str) -> None:
    """Mark the worker stopped, holding no run."""
    with db.transaction() as s:
        worker = s.get(Worker, worker_id)
        if worker is not None:
            worker.stopped_at, worker.run_id = db_now(), None


def live_worker_rows(db: Database, lease_s: float) -> tuple[datetime, list[Worker]]:
    """The database's clock, and the workers that have not stopped and sent a heartbeat
    within ``lease_s`` seconds of it, oldest first (read at that moment)."""
    with db.sessions() as s:
        now = db.now(s)
        rows = s.scalars(select(Worker).where(Worker.stopped_at.is_(None),
                                              Worker.heartbeat_at >= now - timedelta(seconds=lease_s))
                         .order_by(Worker.started_at))
        return now, list(rows)
