"""The statements of a continuation's life as a job (slopetui.queue.branch_jobs holds the
policy): submit, claim, save a point, finish, fail, release, heartbeat, requeue; and the
faces' reads of continuations, their points and their bifurcations. Each function is one
transaction.

The lease is the runs' (slopetui.store.claims): a continuation is held while its heartbeat
(database time) is younger than the lease length, and every write is guarded by
``status = 'running' AND worker_id = me``. A point is saved only as the next one
(``n_points = idx``), so a worker that lost its lease, or a second writer, cannot add a
point twice or leave a gap.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from datetime import timedelta
from typing import Any

from sqlalchemy import RowMapping, bindparam, delete, func, insert, select, update

from slopetui.store.database import Database, rows_changed
from slopetui.store.db_time import db_now
from slopetui.store.models import Bifurcation, BranchPoint, Continuation

#: A continuation's row by column name (a read-only mapping).
ContinuationRow = RowMapping

_HOLDING = ((Continuation.id == bindparam("cid")) & (Continuation.status == "running")
            & (Continuation.worker_id == bindparam("wid")))
_OLDEST_QUEUED = (select(Continuation.id).where(Continuation.status == "queued")
                  .order_by(Continuation.id).limit(1)
                  .with_for_update(skip_locked=True)  # PostgreSQL; SQLite ignores it
                  .scalar_subquery())
_CLAIM = (update(Continuation)
          .where(Continuation.id == _OLDEST_QUEUED, Continuation.status == "queued")
          .values(status="running", worker_id=bindparam("wid"),
                  attempts=Continuation.attempts + 1,
                  started_at=func.coalesce(Continuation.started_at, db_now()),
                  heartbeat_at=db_now(), error=None)
          .returning(*Continuation.__table__.columns))
#: Columns of a point the faces read (all but the resume state).
POINT_COLUMNS = ("idx", "value", "period", "amplitude", "stable", "unstable_count",
                 "leading_re", "leading_im", "multipliers", "flow_index", "translation")


def submit(db: Database, fields: Mapping[str, Any]) -> int:
    """Queue a continuation; returns its id."""
    with db.transaction() as s:
        cid = s.scalar(insert(Continuation).values(**fields).returning(Continuation.id))
    assert cid is not None
    return cid


def claim(db: Database, worker_id: str) -> ContinuationRow | None:
    """Lease the oldest queued continuation to the worker (one attempt charged)."""
    with db.connection() as conn:
        row = conn.execute(_CLAIM, {"wid": worker_id}).first()
    return None if row is None else row._mapping


def saved_points(db: Database, cid: int) -> list[RowMapping]:
    """Every saved point of continuation ``cid``, with its resume state, in order."""
    with db.sessions() as s:
        return [r._mapping for r in s.execute(
            select(*BranchPoint.__table__.columns).where(BranchPoint.continuation_id == cid)
            .order_by(BranchPoint.idx)).all()]


def save_point(db: Database, cid: int, worker_id: str, point: Mapping[str, Any],
               spent_s: float, hopf: tuple[float, float] | None = None) -> bool:
    """Append ``point`` (its ``idx`` must be the next) to a continuation the worker holds,
    add ``spent_s`` to its compute time, and (first point from the Hopf point) record the
    Hopf point. False if the lease was lost or the point is not the next: nothing is
    written."""
    extra = {} if hopf is None else {"hopf_value": hopf[0], "hopf_period": hopf[1]}
    with db.transaction() as s:
        moved = rows_changed(s.execute(
            update(Continuation).where(_HOLDING, Continuation.n_points == point["idx"])
            .values(n_points=Continuation.n_points + 1, heartbeat_at=db_now(),
                    runtime_s=Continuation.runtime_s + spent_s, **extra),
            {"cid": cid, "wid": worker_id}))
        if moved != 1:
            return False
        s.execute(insert(BranchPoint).values(continuation_id=cid, **point))
    return True


def finish(db: Database, cid: int, worker_id: str, end_reason: str, criticality: str | None,
           spent_s: float, bifurcations: Sequence[Mapping[str, Any]]) -> bool:
    """Mark a held continuation done, with why its branch ended and the bifurcations found
    on it. False if the lease was lost (nothing is written)."""
    with db.transaction() as s:
        done = rows_changed(s.execute(
            update(Continuation).where(_HOLDING)
            .values(status="done", finished_at=db_now(), end_reason=end_reason,
                    criticality=criticality, error=None,
                    runtime_s=Continuation.runtime_s + spent_s),
            {"cid": cid, "wid": worker_id}))
        if done != 1:
            return False
        s.execute(delete(Bifurcation).where(Bifurcation.continuation_id == cid))
        for i, bif in enumerate(bifurcations):
            s.execute(insert(Bifurcation).values(continuation_id=cid, idx=i, **bif))
    return True


def fail(db: Database, cid: int, worker_id: str, error: str, *, give_up: bool) -> bool:
    """Record an error on a held continuation: failed for good or back to the queue (its
    saved points stay). False if the lease was lost meanwhile."""
    with db.transaction() as s:
        return rows_changed(s.execute(
            update(Continuation).where(_HOLDING)
            .values(status="failed" if give_up else "queued", error=error[-4000:],
                    worker_id=worker_id if give_up else None,
                    finished_at=db_now() if give_up else None),
            {"cid": cid, "wid": worker_id})) == 1


def release(db: Database, cid: int, worker_id: str) -> bool:
    """Give a held continuation back to the queue (a shutdown, not its fault: its attempt
    is given back); its saved points stay, and the next worker resumes from them."""
    with db.transaction() as s:
        return rows_changed(s.execute(
            update(Continuation).where(_HOLDING)
            .values(status="queued", worker_id=None, attempts=Continuation.attempts - 1),
            {"cid": cid, "wid": worker_id})) == 1


def heartbeat(db: Database, worker_id: str) -> None:
    """Extend the lease of every continuation the worker holds."""
    with db.transaction() as s:
        s.execute(update(Continuation).where(Continuation.status == "running",
                                             Continuation.worker_id == worker_id)
                  .values(heartbeat_at=db_now()))


def _requeue(db: Database, where: Any, reason: str, max_attempts: int) -> tuple[int, int]:
    with db.transaction() as s:
        failed = rows_changed(s.execute(
            update(Continuation).where(where, Continuation.attempts >= max_attempts)
            .values(status="failed", finished_at=db_now(),
                    error=f"{reason}; gave up after {max_attempts} attempts")))
        requeued = rows_changed(s.execute(
            update(Continuation).where(where)
            .values(status="queued", worker_id=None, error=reason)))
    return requeued, failed


def requeue_expired(db: Database, lease_s: float, max_attempts: int) -> tuple[int, int]:
    """Continuations whose lease expired go back to the queue (or fail after
    max_attempts). Returns (requeued, failed)."""
    with db.sessions() as s:
        cutoff = db.now(s) - timedelta(seconds=lease_s)
    expired = (Continuation.status == "running") & (Continuation.heartbeat_at < cutoff)
    return _requeue(db, expired, f"lease expired: no heartbeat for {lease_s:g} s", max_attempts)


def requeue_worker(db: Database, worker_id: str, reason: str,
                   max_attempts: int) -> tuple[int, int]:
    """The continuations of a worker known to be dead go back at once."""
    held = (Continuation.status == "running") & (Continuation.worker_id == worker_id)
    return _requeue(db, held, reason, max_attempts)


def waiting(db: Database) -> int:
    """Continuations queued or running (a worker may still have to compute them)."""
    with db.sessions() as s:
        n = s.scalar(select(func.count()).select_from(Continuation)
                     .where(Continuation.status.in_(("queued", "running"))))
    return int(n or 0)


# -- the faces' reads --

def status_counts(db: Database) -> dict[str, int]:
    """Continuations per status."""
    with db.sessions() as s:
        return {status: int(n) for status, n in s.execute(
            select(Continuation.status, func.count()).group_by(Continuation.status)).all()}


def held(db: Database) -> dict[str, int]:
    """The continuation each worker computes now, by worker id."""
    with db.sessions() as s:
        return {str(wid): int(cid) for wid, cid in s.execute(
            select(Continuation.worker_id, Continuation.id)
            .where(Continuation.status == "running")).all()}


def continuations(db: Database) -> list[ContinuationRow]:
    """Every continuation, newest first."""
    with db.sessions() as s:
        return [r._mapping for r in s.execute(
            select(*Continuation.__table__.columns).order_by(Continuation.id.desc())).all()]


def continuation(db: Database, cid: int) -> ContinuationRow | None:
    with db.sessions() as s:
        row = s.execute(select(*Continuation.__table__.columns)
                        .where(Continuation.id == cid)).first()
    return None if row is None else row._mapping


def points(db: Database, cid: int) -> list[RowMapping]:
    """The branch's points (without their resume state), in order."""
    cols = [getattr(BranchPoint, n) for n in POINT_COLUMNS]
    with db.sessions() as s:
        return [r._mapping for r in s.execute(
            select(*cols).where(BranchPoint.continuation_id == cid)
            .order_by(BranchPoint.idx)).all()]


def bifurcations(db: Database, cid: int) -> list[RowMapping]:
    """The bifurcations found on a finished continuation's branch, in branch order."""
    with db.sessions() as s:
        return [r._mapping for r in s.execute(
            select(*Bifurcation.__table__.columns).where(Bifurcation.continuation_id == cid)
            .order_by(Bifurcation.idx)).all()]
