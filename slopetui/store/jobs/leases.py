"""The lease every job of the queue is held under, one implementation for every job table
(runs: slopetui.store.runs.claims; continuations and hysteresis sweeps:
slopetui.store.jobs.point_jobs): the holder's guard, fail, release, heartbeat and requeue.

A worker holds a job while its heartbeat (database time) is younger than the lease
length; ``requeue_expired`` hands the jobs of silent workers to others, and fails a job
after ``max_attempts``. Every write on a held job is guarded by ``status = 'running' AND
worker_id = me`` (``Lease.holding``), so a worker that lost its lease cannot write a
second result for a job that another worker has taken over.

A job held but never started (``status = 'running' AND started_at IS NULL``: a run of a
batch claimed and not yet begun, slopetui.store.runs.claims) goes back to the queue as it came,
with no attempt charged and no error; a point-by-point job is started at its claim, so
none of its rows is ever in that state.

Lock order. The statements that write the worker's row (``workers``) write it after the
job rows, and the statements that span several job tables take them in one order (the
caller's, the queue's registry of job kinds): with the worker's row first, a heartbeat
and a write of the same worker on two connections deadlocked on PostgreSQL
(DeadlockDetected on "runs"; SQLite's BEGIN IMMEDIATE serialises them and hid it;
tests/integration/test_lock_order_postgres.py).
"""

from __future__ import annotations

from collections.abc import Sequence
from datetime import timedelta
from typing import Any

from sqlalchemy import ColumnElement, bindparam, func, select, update
from sqlalchemy.orm import Session

from slopetui.store.database import Database, rows_changed
from slopetui.store.db_time import db_now
from slopetui.store.models import LeasedJob, Run, Worker


class Lease:
    """The lease statements of one job table (``job``: ``Run`` or a ``LeasedJob``).
    ``pointed``: the worker's row names the job it computes (``workers.run_id``, runs
    only), and a fail or a release clears it in the same transaction."""

    def __init__(self, job: type[LeasedJob] | type[Run], *, pointed: bool = False) -> None:
        self.job = job
        self.pointed = pointed
        #: The holder's guard on every write to a held job (bind ``jid`` and ``wid``).
        self.holding: ColumnElement[bool] = (
            (job.id == bindparam("jid")) & (job.status == "running")
            & (job.worker_id == bindparam("wid")))

    def _unpoint(self, s: Session, worker_id: str) -> None:
        if self.pointed:  # after the job's row: the lock order (module docstring)
            s.execute(update(Worker).where(Worker.id == worker_id).values(run_id=None))

    def fail(self, db: Database, job_id: int, worker_id: str, error: str, *,
             give_up: bool) -> bool:
        """Record an error on a held job: failed for good (``give_up``) or back to the
        queue (what it saved stays). False if the lease was lost meanwhile."""
        with db.transaction() as s:
            n = rows_changed(s.execute(
                update(self.job).where(self.holding)
                .values(status="failed" if give_up else "queued", error=error[-4000:],
                        worker_id=worker_id if give_up else None,
                        finished_at=db_now() if give_up else None),
                {"jid": job_id, "wid": worker_id}))
            self._unpoint(s, worker_id)
        return n == 1

    def release(self, db: Database, job_id: int, worker_id: str, *, started: bool) -> bool:
        """Give a held job back to the queue unfinished (a shutdown, not its fault); a
        ``started`` job's attempt is given back too. False if the lease was lost
        meanwhile."""
        with db.transaction() as s:
            n = rows_changed(s.execute(
                update(self.job).where(self.holding)
                .values(status="queued", worker_id=None,
                        attempts=self.job.attempts - int(started)),
                {"jid": job_id, "wid": worker_id}))
            self._unpoint(s, worker_id)
        return n == 1

    def extend(self, s: Session, worker_id: str) -> None:
        """In the caller's transaction: extend the lease of every job of this table the
        worker holds (one, or a batch)."""
        s.execute(update(self.job).where(self.job.status == "running",
                                         self.job.worker_id == worker_id)
                  .values(heartbeat_at=db_now()))

    def requeue(self, s: Session, where: Any, reason: str,
                max_attempts: int) -> tuple[int, int]:
        """In the caller's transaction: the held jobs ``where`` selects back to the queue
        (those never started as they came), or failed once they have had
        ``max_attempts``. Returns (requeued, failed)."""
        job = self.job
        unstarted = s.execute(update(job).where(where, job.started_at.is_(None))
                              .values(status="queued", worker_id=None))
        failed = s.execute(update(job).where(where, job.attempts >= max_attempts)
                           .values(status="failed", finished_at=db_now(),
                                   error=f"{reason}; gave up after {max_attempts} attempts"))
        requeued = s.execute(update(job).where(where)
                             .values(status="queued", worker_id=None, error=reason))
        return rows_changed(requeued) + rows_changed(unstarted), rows_changed(failed)

    def expired(self, cutoff: Any) -> ColumnElement[bool]:
        """The held jobs whose last heartbeat is older than ``cutoff`` (database time)."""
        return (self.job.status == "running") & (self.job.heartbeat_at < cutoff)

    def held_by(self, worker_id: str) -> ColumnElement[bool]:
        """The jobs ``worker_id`` holds."""
        return (self.job.status == "running") & (self.job.worker_id == worker_id)

    # -- the reads any job table answers --

    def status_counts(self, db: Database) -> dict[str, int]:
        """Jobs per status."""
        with db.sessions() as s:
            return {status: int(n) for status, n in s.execute(
                select(self.job.status, func.count()).group_by(self.job.status)).all()}

    def held(self, db: Database) -> dict[str, int]:
        """A job each worker computes now, by worker id (of a batch, its newest)."""
        with db.sessions() as s:
            return {str(wid): int(job_id) for wid, job_id in s.execute(
                select(self.job.worker_id, self.job.id)
                .where(self.job.status == "running").order_by(self.job.id)).all()}


# The statements over every job table at once: one transaction each, the tables in the
# order given (the queue's registry of job kinds), the worker's row last.

def heartbeat(db: Database, leases: Sequence[Lease], worker_id: str) -> None:
    """Extend the lease of every job the worker holds, in every table, and mark the
    worker alive."""
    with db.transaction() as s:
        for lease in leases:
            lease.extend(s, worker_id)
        s.execute(update(Worker).where(Worker.id == worker_id).values(heartbeat_at=db_now()))


def requeue_expired(db: Database, leases: Sequence[Lease], lease_s: float,
                    max_attempts: int) -> tuple[int, int]:
    """Jobs whose lease expired go back to the queue (or fail after max_attempts).
    Returns (requeued, failed), over every table."""
    reason = f"lease expired: no heartbeat for {lease_s:g} s"
    with db.transaction() as s:
        cutoff = db.now(s) - timedelta(seconds=lease_s)
        counts = [lease.requeue(s, lease.expired(cutoff), reason, max_attempts)
                  for lease in leases]
    return sum(n for n, _ in counts), sum(n for _, n in counts)


def requeue_worker(db: Database, leases: Sequence[Lease], worker_id: str, reason: str,
                   max_attempts: int) -> tuple[int, int]:
    """The jobs of a worker known to be dead go back at once, without waiting for the
    lease, and the worker is marked stopped. Returns (requeued, failed), over every
    table."""
    with db.transaction() as s:
        counts = [lease.requeue(s, lease.held_by(worker_id), reason, max_attempts)
                  for lease in leases]
        s.execute(update(Worker).where(Worker.id == worker_id)
                  .values(run_id=None, stopped_at=db_now()))
    return sum(n for n, _ in counts), sum(n for _, n in counts)
