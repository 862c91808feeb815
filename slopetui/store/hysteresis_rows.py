"""The statements of a hysteresis sweep's life as a job (slopetui.queue.hysteresis_jobs
holds the policy): submit, claim, save a point, finish, fail, release, heartbeat, requeue;
and the faces' reads of the sweeps and their points. Each function is one transaction.

The lease is the runs' and the continuations' (slopetui.store.claims, branch_rows): a sweep
is held while its heartbeat (database time) is younger than the lease length, and every
write is guarded by ``status = 'running' AND worker_id = me``. A point is saved only as
the next one (``n_done = idx``), so a worker that lost its lease, or a second writer,
cannot add a point twice or leave a gap.
"""

from __future__ import annotations

from collections.abc import Mapping
from datetime import timedelta
from typing import Any

from sqlalchemy import RowMapping, bindparam, func, insert, select, update

from slopetui.store.database import Database, rows_changed
from slopetui.store.db_time import db_now
from slopetui.store.models import HysteresisPoint, HysteresisSweep

#: A hysteresis sweep's row by column name (a read-only mapping).
HysteresisRow = RowMapping

_HOLDING = ((HysteresisSweep.id == bindparam("sid")) & (HysteresisSweep.status == "running")
            & (HysteresisSweep.worker_id == bindparam("wid")))
_OLDEST_QUEUED = (select(HysteresisSweep.id).where(HysteresisSweep.status == "queued")
                  .order_by(HysteresisSweep.id).limit(1)
                  .with_for_update(skip_locked=True)  # PostgreSQL; SQLite ignores it
                  .scalar_subquery())
_CLAIM = (update(HysteresisSweep)
          .where(HysteresisSweep.id == _OLDEST_QUEUED, HysteresisSweep.status == "queued")
          .values(status="running", worker_id=bindparam("wid"),
                  attempts=HysteresisSweep.attempts + 1,
                  started_at=func.coalesce(HysteresisSweep.started_at, db_now()),
                  heartbeat_at=db_now(), error=None)
          .returning(*HysteresisSweep.__table__.columns))
#: Columns of a point the faces read (all but the state handed over).
POINT_COLUMNS = ("idx", "direction", "value", "regime", "detail", "amplitude", "growth",
                 "jumped")


def submit(db: Database, fields: Mapping[str, Any]) -> int:
    """Queue a hysteresis sweep; returns its id."""
    with db.transaction() as s:
        sid = s.scalar(insert(HysteresisSweep).values(**fields).returning(HysteresisSweep.id))
    assert sid is not None
    return sid


def claim(db: Database, worker_id: str) -> HysteresisRow | None:
    """Lease the oldest queued hysteresis sweep to the worker (one attempt charged)."""
    with db.connection() as conn:
        row = conn.execute(_CLAIM, {"wid": worker_id}).first()
    return None if row is None else row._mapping


def saved_points(db: Database, sid: int) -> list[RowMapping]:
    """Every saved point of sweep ``sid``, with the state it hands over, in order."""
    with db.sessions() as s:
        return [r._mapping for r in s.execute(
            select(*HysteresisPoint.__table__.columns).where(HysteresisPoint.sweep_id == sid)
            .order_by(HysteresisPoint.idx)).all()]


def save_point(db: Database, sid: int, worker_id: str, point: Mapping[str, Any],
               spent_s: float) -> bool:
    """Append ``point`` (its ``idx`` must be the next) to a sweep the worker holds, and add
    ``spent_s`` to its compute time. False if the lease was lost or the point is not the
    next: nothing is written."""
    with db.transaction() as s:
        moved = rows_changed(s.execute(
            update(HysteresisSweep).where(_HOLDING, HysteresisSweep.n_done == point["idx"])
            .values(n_done=HysteresisSweep.n_done + 1, heartbeat_at=db_now(),
                    runtime_s=HysteresisSweep.runtime_s + spent_s),
            {"sid": sid, "wid": worker_id}))
        if moved != 1:
            return False
        s.execute(insert(HysteresisPoint).values(sweep_id=sid, **point))
    return True


def finish(db: Database, sid: int, worker_id: str, onset_up: float | None,
           offset_down: float | None, spent_s: float) -> bool:
    """Mark a held sweep done, with where each branch changes regime. False if the lease
    was lost (nothing is written)."""
    with db.transaction() as s:
        return rows_changed(s.execute(
            update(HysteresisSweep).where(_HOLDING)
            .values(status="done", finished_at=db_now(), onset_up=onset_up,
                    offset_down=offset_down, error=None,
                    runtime_s=HysteresisSweep.runtime_s + spent_s),
            {"sid": sid, "wid": worker_id})) == 1


def fail(db: Database, sid: int, worker_id: str, error: str, *, give_up: bool) -> bool:
    """Record an error on a held sweep: failed for good or back to the queue (its saved
    points stay). False if the lease was lost meanwhile."""
    with db.transaction() as s:
        return rows_changed(s.execute(
            update(HysteresisSweep).where(_HOLDING)
            .values(status="failed" if give_up else "queued", error=error[-4000:],
                    worker_id=worker_id if give_up else None,
                    finished_at=db_now() if give_up else None),
            {"sid": sid, "wid": worker_id})) == 1


def release(db: Database, sid: int, worker_id: str) -> bool:
    """Give a held sweep back to the queue (a shutdown, not its fault: its attempt is given
    back); its saved points stay, and the next worker resumes from them."""
    with db.transaction() as s:
        return rows_changed(s.execute(
            update(HysteresisSweep).where(_HOLDING)
            .values(status="queued", worker_id=None, attempts=HysteresisSweep.attempts - 1),
            {"sid": sid, "wid": worker_id})) == 1


def heartbeat(db: Database, worker_id: str) -> None:
    """Extend the lease of every hysteresis sweep the worker holds."""
    with db.transaction() as s:
        s.execute(update(HysteresisSweep).where(HysteresisSweep.status == "running",
                                                HysteresisSweep.worker_id == worker_id)
                  .values(heartbeat_at=db_now()))


def _requeue(db: Database, where: Any, reason: str, max_attempts: int) -> tuple[int, int]:
    with db.transaction() as s:
        failed = rows_changed(s.execute(
            update(HysteresisSweep).where(where, HysteresisSweep.attempts >= max_attempts)
            .values(status="failed", finished_at=db_now(),
                    error=f"{reason}; gave up after {max_attempts} attempts")))
        requeued = rows_changed(s.execute(
            update(HysteresisSweep).where(where)
            .values(status="queued", worker_id=None, error=reason)))
    return requeued, failed


def requeue_expired(db: Database, lease_s: float, max_attempts: int) -> tuple[int, int]:
    """Sweeps whose lease expired go back to the queue (or fail after max_attempts).
    Returns (requeued, failed)."""
    with db.sessions() as s:
        cutoff = db.now(s) - timedelta(seconds=lease_s)
    expired = (HysteresisSweep.status == "running") & (HysteresisSweep.heartbeat_at < cutoff)
    return _requeue(db, expired, f"lease expired: no heartbeat for {lease_s:g} s", max_attempts)


def requeue_worker(db: Database, worker_id: str, reason: str,
                   max_attempts: int) -> tuple[int, int]:
    """The sweeps of a worker known to be dead go back at once."""
    held = (HysteresisSweep.status == "running") & (HysteresisSweep.worker_id == worker_id)
    return _requeue(db, held, reason, max_attempts)


def waiting(db: Database) -> int:
    """Hysteresis sweeps queued or running (a worker may still have to compute them)."""
    with db.sessions() as s:
        n = s.scalar(select(func.count()).select_from(HysteresisSweep)
                     .where(HysteresisSweep.status.in_(("queued", "running"))))
    return int(n or 0)


# -- the faces' reads --

def status_counts(db: Database) -> dict[str, int]:
    """Hysteresis sweeps per status."""
    with db.sessions() as s:
        return {status: int(n) for status, n in s.execute(
            select(HysteresisSweep.status, func.count()).group_by(HysteresisSweep.status)).all()}


def held(db: Database) -> dict[str, int]:
    """The hysteresis sweep each worker computes now, by worker id."""
    with db.sessions() as s:
        return {str(wid): int(sid) for wid, sid in s.execute(
            select(HysteresisSweep.worker_id, HysteresisSweep.id)
            .where(HysteresisSweep.status == "running")).all()}


def hysteresis_sweeps(db: Database) -> list[HysteresisRow]:
    """Every hysteresis sweep, newest first."""
    with db.sessions() as s:
        return [r._mapping for r in s.execute(
            select(*HysteresisSweep.__table__.columns)
            .order_by(HysteresisSweep.id.desc())).all()]


def hysteresis_sweep(db: Database, sid: int) -> HysteresisRow | None:
    with db.sessions() as s:
        row = s.execute(select(*HysteresisSweep.__table__.columns)
                        .where(HysteresisSweep.id == sid)).first()
    return None if row is None else row._mapping


def points(db: Database, sid: int) -> list[RowMapping]:
    """The sweep's points (without the state they hand over), in order."""
    cols = [getattr(HysteresisPoint, n) for n in POINT_COLUMNS]
    with db.sessions() as s:
        return [r._mapping for r in s.execute(
            select(*cols).where(HysteresisPoint.sweep_id == sid)
            .order_by(HysteresisPoint.idx)).all()]
