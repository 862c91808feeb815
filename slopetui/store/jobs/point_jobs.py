"""The statements every job computed point by point under a lease shares (continuations:
slopetui.store.jobs.continuations, hysteresis sweeps: slopetui.store.jobs.hysteresis_sweeps): submit,
claim, save the next point, mark done, and the reads the faces make of any such table;
its lease (fail, release, heartbeat, requeue) is every job's (slopetui.store.jobs.leases).
``PointJobs`` builds them once for one job model (a ``LeasedJob``), its points' model, the
column counting the saved points, and the frozen dataclasses its rows are read into (a
job's row, a point as the faces read it, a point with what a resumption needs: their
fields name the columns read). The rows modules keep their own functions, with what
differs (a finish's results), on top of it. Each method is one transaction, except
``mark_done``, which runs in the caller's so that it can write more beside it.

A point is saved only as the next one (the counter equal to its ``idx``), so a worker that
lost its lease, or a second writer, cannot add a point twice or leave a gap.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from dataclasses import fields as dataclass_fields
from datetime import datetime
from typing import Any, Generic, TypeVar

from sqlalchemy import Row, bindparam, case, func, insert, literal, select, update
from sqlalchemy.orm import Session

from slopetui.store.database import Database, rows_changed
from slopetui.store.db_time import db_now
from slopetui.store.jobs.leases import Lease
from slopetui.store.models import Base, LeasedJob

#: A job's row, a point as the faces read it, a saved point with its resume state.
JobT = TypeVar("JobT")
PointT = TypeVar("PointT")
SavedT = TypeVar("SavedT")
T = TypeVar("T")


@dataclass(frozen=True, slots=True)
class LeasedRow:
    """The queue's columns of a job's row (slopetui.store.models.LeasedJob), and its
    compute time over every attempt (s)."""

    id: int
    status: str
    worker_id: str | None
    attempts: int
    created_at: datetime
    started_at: datetime | None
    heartbeat_at: datetime | None
    finished_at: datetime | None
    error: str | None
    runtime_s: float


def columns(model: type[Any], record: type[Any]) -> list[Any]:
    """The columns of ``model`` that the dataclass ``record`` has fields for, in its
    order."""
    return [getattr(model, f.name) for f in dataclass_fields(record)]


def record_of(record: Callable[..., JobT], row: Row[Any]) -> JobT:
    """A row read with ``columns(model, record)`` as a ``record`` (a dataclass)."""
    return record(*row)


#: A job's ``engine`` when workers of different engines computed its points (_engine_after).
MIXED_ENGINES = "mixed"


class PointJobs(Generic[JobT, PointT, SavedT]):
    """The statements and reads of one table of jobs (``job``), whose points are rows of
    ``point`` naming their job in column ``parent`` and counted, as saved, in the job's
    column ``counter``; read as ``row`` (a job), ``point_row`` (a point for the faces) and
    ``saved_row`` (a point with its resume state)."""

    def __init__(self, job: type[LeasedJob], point: type[Base], parent: str, counter: str,
                 *, row: type[JobT], point_row: type[PointT], saved_row: type[SavedT]) -> None:
        self.job = job
        self.point = point
        self.lease = Lease(job)
        #: Jobs per status; the job each worker computes now, by worker id.
        self.status_counts = self.lease.status_counts
        self.held = self.lease.held
        self.row_type, self.point_type, self.saved_type = row, point_row, saved_row
        self._parent = parent
        self._counter = counter
        self._point_parent = point.__table__.c[parent]
        self._point_idx = point.__table__.c.idx
        self._count = job.__table__.c[counter]
        self._row_columns = columns(job, row)
        # Prebuilt once, as the runs' claim (slopetui.store.runs.claims): the workers' hot path.
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
                       .returning(*self._row_columns))

    def _engine_after(self, digest: str) -> Any:
        """The job's ``engine`` once a worker of engine ``digest`` has saved to it: the
        worker's, if it is the first to save (no point yet: the digest written at queue time
        is replaced) or every earlier point was saved by the same engine; else "mixed" (a job
        resumed by workers of different engines: its points come from more than one, and a
        String(16) column holds no list of them)."""
        job: Any = self.job
        return case((self._count == 0, literal(digest)), (job.engine == digest, job.engine),
                    else_=literal(MIXED_ENGINES))

    def _engine_column(self, digest: str | None) -> dict[str, Any]:
        return {} if digest is None else {"engine": self._engine_after(digest)}

    # -- a job's life --

    def submit(self, db: Database, fields: Mapping[str, Any]) -> int:
        """Queue a job; returns its id."""
        with db.transaction() as s:
            job_id = s.scalar(insert(self.job).values(**fields).returning(self.job.id))
        assert job_id is not None
        return job_id

    def claim(self, db: Database, worker_id: str) -> JobT | None:
        """Lease the oldest queued job to the worker (one attempt charged, started)."""
        with db.connection() as conn:
            row = conn.execute(self._claim, {"wid": worker_id}).first()
        return None if row is None else record_of(self.row_type, row)

    def save_point(self, db: Database, job_id: int, worker_id: str, point: Mapping[str, Any],
                   spent_s: float, engine: str | None = None, **extra: Any) -> bool:
        """Append ``point`` (its ``idx`` must be the next) to a job the worker holds, add
        ``spent_s`` to its compute time, name the worker's ``engine`` (_engine_after; None,
        a synthetic point of a test: the job's is kept) and set the job's columns
        ``extra``. False if the lease was lost or the point is not the next: nothing is
        written."""
        job = self.job
        with db.transaction() as s:
            moved = rows_changed(s.execute(
                update(job).where(self.lease.holding, self._count == point["idx"])
                .values({self._counter: self._count + 1, "heartbeat_at": db_now(),
                         "runtime_s": job.runtime_s + spent_s,
                         **self._engine_column(engine), **extra}),
                {"jid": job_id, "wid": worker_id}))
            if moved != 1:
                return False
            s.execute(insert(self.point).values({self._parent: job_id, **point}))
        return True

    def mark_done(self, s: Session, job_id: int, worker_id: str, spent_s: float,
                  engine: str | None = None, **results: Any) -> bool:
        """In the caller's transaction ``s``: mark a held job done with its ``results``
        (columns), computed by a worker of ``engine`` (_engine_after), adding ``spent_s`` to
        its compute time. False if the lease was lost (nothing is written)."""
        job = self.job
        return rows_changed(s.execute(
            update(job).where(self.lease.holding)
            .values(status="done", finished_at=db_now(), error=None,
                    runtime_s=job.runtime_s + spent_s, **self._engine_column(engine),
                    **results),
            {"jid": job_id, "wid": worker_id})) == 1

    def fail(self, db: Database, job_id: int, worker_id: str, error: str, *,
             give_up: bool) -> bool:
        """Record an error on a held job: failed for good or back to the queue (its saved
        points stay). False if the lease was lost meanwhile."""
        return self.lease.fail(db, job_id, worker_id, error, give_up=give_up)

    def release(self, db: Database, job_id: int, worker_id: str) -> bool:
        """Give a held job back to the queue (a shutdown, not its fault: its attempt, charged
        at the claim, is given back); its saved points stay, and the next worker resumes
        from them."""
        return self.lease.release(db, job_id, worker_id, started=True)

    # -- the reads --

    def saved_points(self, db: Database, job_id: int) -> list[SavedT]:
        """Every saved point of a job, with what a resumption needs, in order."""
        return self._points(db, job_id, self.saved_type)

    def points(self, db: Database, job_id: int) -> list[PointT]:
        """A job's saved points as the faces read them, in order."""
        return self._points(db, job_id, self.point_type)

    def _points(self, db: Database, job_id: int, record: type[T]) -> list[T]:
        with db.sessions() as s:
            return [record_of(record, r) for r in s.execute(
                select(*columns(self.point, record)).where(self._point_parent == job_id)
                .order_by(self._point_idx)).all()]

    def newest_first(self, db: Database) -> list[JobT]:
        """Every job's row, newest first."""
        with db.sessions() as s:
            return [record_of(self.row_type, r) for r in s.execute(
                select(*self._row_columns).order_by(self.job.id.desc())).all()]

    def row(self, db: Database, job_id: int) -> JobT | None:
        """Job ``job_id``'s row; None if there is none."""
        with db.sessions() as s:
            found = s.execute(select(*self._row_columns)
                              .where(self.job.id == job_id)).first()
        return None if found is None else record_of(self.row_type, found)
