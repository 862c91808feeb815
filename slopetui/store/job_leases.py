"""The statements every job computed point by point under a lease shares (continuations:
slopetui.store.branch_rows, hysteresis sweeps: slopetui.store.hysteresis_rows): submit,
claim, save the next point, mark done, fail, release, heartbeat, requeue, and the reads
the faces make of any such table. ``JobLeases`` builds them once for one job model (a
``LeasedJob``), its points' model and the column counting the saved points; the rows
modules keep their own functions, with what differs (a finish's results, the columns a
face reads), on top of it. Each method is one transaction, except ``mark_done``, which
runs in the caller's so that it can write more beside it.

The lease is the runs' (slopetui.store.claims): a job is held while its heartbeat
(database time) is younger than the lease length, and every write is guarded by
``status = 'running' AND worker_id = me``. A point is saved only as the next one (the
counter equal to its ``idx``), so a worker that lost its lease, or a second writer,
cannot add a point twice or leave a gap.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from datetime import timedelta
from typing import Any

from sqlalchemy import RowMapping, bindparam, func, insert, select, update
from sqlalchemy.orm import Session

from slopetui.store.database import Database, rows_changed
from slopetui.store.db_time import db_now
from slopetui.store.models import Base, LeasedJob


class JobLeases:
    """The lease statements and reads of one table of jobs (``job``), whose points are
    rows of ``point`` naming their job in column ``parent`` and counted, as saved, in the
    job's column ``counter``."""

    def __init__(self, job: type[LeasedJob], point: type[Base], parent: str,
                 counter: str) -> None:
        self.job = job
        self.point = point
        self._parent = parent
        self._counter = counter
        self._point_parent = point.__table__.c[parent]
        self._point_idx = point.__table__.c.idx
        self._count = job.__table__.c[counter]
        # Prebuilt once, as the runs' claim (slopetui.store.claims): the workers' hot path.
        self._holding = ((job.id == bindparam("job")) & (job.status == "running")
                         & (job.worker_id == bindparam("wid")))
        oldest_queued = (select(job.id).where(job.status == "queued")
                         .order_by(job.id).limit(1)
                         .with_for_update(skip_locked=True)  # PostgreSQL; SQLite ignores it
                         .scalar_subquery())
        self._claim = (update(job)
                       .where(job.id == oldest_queued, job.status == "queued")
                       .values(status="running", worker_id=bindparam("wid"),
                               attempts=job.attempts + 1,
                               started_at=func.coalesce(job.started_at, db_now()),
                               heartbeat_at=db_now(), error=None)
                       .returning(*job.__table__.columns))

    # -- a job's life --

    def submit(self, db: Database, fields: Mapping[str, Any]) -> int:
        """Queue a job; returns its id."""
        with db.transaction() as s:
            job_id = s.scalar(insert(self.job).values(**fields).returning(self.job.id))
        assert job_id is not None
        return job_id

    def claim(self, db: Database, worker_id: str) -> RowMapping | None:
        """Lease the oldest queued job to the worker (one attempt charged)."""
        with db.connection() as conn:
            row = conn.execute(self._claim, {"wid": worker_id}).first()
        return None if row is None else row._mapping

    def save_point(self, db: Database, job_id: int, worker_id: str, point: Mapping[str, Any],
                   spent_s: float, **extra: Any) -> bool:
        """Append ``point`` (its ``idx`` must be the next) to a job the worker holds, add
        ``spent_s`` to its compute time and set the job's columns ``extra``. False if the
        lease was lost or the point is not the next: nothing is written."""
        job = self.job
        with db.transaction() as s:
            moved = rows_changed(s.execute(
                update(job).where(self._holding, self._count == point["idx"])
                .values({self._counter: self._count + 1, "heartbeat_at": db_now(),
                         "runtime_s": job.runtime_s + spent_s, **extra}),
                {"job": job_id, "wid": worker_id}))
            if moved != 1:
                return False
            s.execute(insert(self.point).values({self._parent: job_id, **point}))
        return True

    def mark_done(self, s: Session, job_id: int, worker_id: str, spent_s: float,
                  **results: Any) -> bool:
        """In the caller's transaction ``s``: mark a held job done with its ``results``
        (columns), adding ``spent_s`` to its compute time. False if the lease was lost
        (nothing is written)."""
        job = self.job
        return rows_changed(s.execute(
            update(job).where(self._holding)
            .values(status="done", finished_at=db_now(), error=None,
                    runtime_s=job.runtime_s + spent_s, **results),
            {"job": job_id, "wid": worker_id})) == 1

    def fail(self, db: Database, job_id: int, worker_id: str, error: str, *,
             give_up: bool) -> bool:
        """Record an error on a held job: failed for good or back to the queue (its saved
        points stay). False if the lease was lost meanwhile."""
        with db.transaction() as s:
            return rows_changed(s.execute(
                update(self.job).where(self._holding)
                .values(status="failed" if give_up else "queued", error=error[-4000:],
                        worker_id=worker_id if give_up else None,
                        finished_at=db_now() if give_up else None),
                {"job": job_id, "wid": worker_id})) == 1

    def release(self, db: Database, job_id: int, worker_id: str) -> bool:
        """Give a held job back to the queue (a shutdown, not its fault: its attempt is
        given back); its saved points stay, and the next worker resumes from them."""
        with db.transaction() as s:
            return rows_changed(s.execute(
                update(self.job).where(self._holding)
                .values(status="queued", worker_id=None, attempts=self.job.attempts - 1),
                {"job": job_id, "wid": worker_id})) == 1

    def heartbeat(self, db: Database, worker_id: str) -> None:
        """Extend the lease of every job of this table the worker holds."""
        with db.transaction() as s:
            s.execute(update(self.job).where(self.job.status == "running",
                                             self.job.worker_id == worker_id)
                      .values(heartbeat_at=db_now()))

    def _requeue(self, db: Database, where: Any, reason: str,
                 max_attempts: int) -> tuple[int, int]:
        """The jobs ``where`` selects back to the queue, or failed once they have had
        ``max_attempts``. Returns (requeued, failed)."""
        job = self.job
        with db.transaction() as s:
            failed = rows_changed(s.execute(
                update(job).where(where, job.attempts >= max_attempts)
                .values(status="failed", finished_at=db_now(),
                        error=f"{reason}; gave up after {max_attempts} attempts")))
            requeued = rows_changed(s.execute(
                update(job).where(where)
                .values(status="queued", worker_id=None, error=reason)))
        return requeued, failed

    def requeue_expired(self, db: Database, lease_s: float,
                        max_attempts: int) -> tuple[int, int]:
        """Jobs whose lease expired go back to the queue (or fail after max_attempts).
        Returns (requeued, failed)."""
        with db.sessions() as s:
            cutoff = db.now(s) - timedelta(seconds=lease_s)
        expired = (self.job.status == "running") & (self.job.heartbeat_at < cutoff)
        return self._requeue(db, expired, f"lease expired: no heartbeat for {lease_s:g} s",
                             max_attempts)

    def requeue_worker(self, db: Database, worker_id: str, reason: str,
                       max_attempts: int) -> tuple[int, int]:
        """The jobs of a worker known to be dead go back at once."""
        held = (self.job.status == "running") & (self.job.worker_id == worker_id)
        return self._requeue(db, held, reason, max_attempts)

    # -- the reads --

    def saved_points(self, db: Database, job_id: int) -> list[RowMapping]:
        """Every saved point of a job, every column (what a resumption needs), in order."""
        return self.points(db, job_id, [c.name for c in self.point.__table__.columns])

    def points(self, db: Database, job_id: int, names: Sequence[str]) -> list[RowMapping]:
        """The columns ``names`` of a job's saved points, in order."""
        cols = [getattr(self.point, n) for n in names]
        with db.sessions() as s:
            return [r._mapping for r in s.execute(
                select(*cols).where(self._point_parent == job_id)
                .order_by(self._point_idx)).all()]

    def status_counts(self, db: Database) -> dict[str, int]:
        """Jobs per status."""
        with db.sessions() as s:
            return {status: int(n) for status, n in s.execute(
                select(self.job.status, func.count()).group_by(self.job.status)).all()}

    def held(self, db: Database) -> dict[str, int]:
        """The job each worker computes now, by worker id."""
        with db.sessions() as s:
            return {str(wid): int(job_id) for wid, job_id in s.execute(
                select(self.job.worker_id, self.job.id)
                .where(self.job.status == "running")).all()}

    def newest_first(self, db: Database) -> list[RowMapping]:
        """Every job's row, newest first."""
        with db.sessions() as s:
            return [r._mapping for r in s.execute(
                select(*self.job.__table__.columns).order_by(self.job.id.desc())).all()]

    def row(self, db: Database, job_id: int) -> RowMapping | None:
        """Job ``job_id``'s row; None if there is none."""
        with db.sessions() as s:
            found = s.execute(select(*self.job.__table__.columns)
                              .where(self.job.id == job_id)).first()
        return None if found is None else found._mapping
