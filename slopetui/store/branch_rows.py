"""The statements of a continuation's life as a job (slopetui.queue.branch_jobs holds the
policy): submit, claim, save a point, finish, fail, release, heartbeat, requeue; and the
faces' reads of continuations, their points and their bifurcations. Each function is one
transaction.

The lease and its statements are every point-by-point job's (slopetui.store.job_leases):
a continuation's points are counted in ``n_points``, and a point is saved only as the
next one. What is a continuation's own: the Hopf point recorded with the first point, and
the bifurcations written with its finish.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from sqlalchemy import RowMapping, delete, insert, select

from slopetui.store.database import Database
from slopetui.store.job_leases import JobLeases
from slopetui.store.models import Bifurcation, BranchPoint, Continuation

#: A continuation's row by column name (a read-only mapping).
ContinuationRow = RowMapping

#: Columns of a point the faces read (all but the resume state).
POINT_COLUMNS = ("idx", "value", "period", "amplitude", "stable", "unstable_count",
                 "leading_re", "leading_im", "multipliers", "flow_index", "translation")

_JOBS = JobLeases(Continuation, BranchPoint, parent="continuation_id", counter="n_points")

# The statements every point-by-point job shares (slopetui.store.job_leases), by the names
# the queue and the faces call: a continuation's id is the job id.
submit = _JOBS.submit
claim = _JOBS.claim
#: Every saved point of a continuation, with its resume state, in order.
saved_points = _JOBS.saved_points
fail = _JOBS.fail
release = _JOBS.release
heartbeat = _JOBS.heartbeat
requeue_expired = _JOBS.requeue_expired
requeue_worker = _JOBS.requeue_worker
status_counts = _JOBS.status_counts
held = _JOBS.held
#: Every continuation, newest first; one continuation's row (None: no such id).
continuations = _JOBS.newest_first
continuation = _JOBS.row


def save_point(db: Database, cid: int, worker_id: str, point: Mapping[str, Any],
               spent_s: float, hopf: tuple[float, float] | None = None) -> bool:
    """Append ``point`` (its ``idx`` must be the next) to a continuation the worker holds,
    add ``spent_s`` to its compute time, and (first point from the Hopf point) record the
    Hopf point. False if the lease was lost or the point is not the next: nothing is
    written."""
    extra = {} if hopf is None else {"hopf_value": hopf[0], "hopf_period": hopf[1]}
    return _JOBS.save_point(db, cid, worker_id, point, spent_s, **extra)


def finish(db: Database, cid: int, worker_id: str, end_reason: str, criticality: str | None,
           spent_s: float, bifurcations: Sequence[Mapping[str, Any]]) -> bool:
    """Mark a held continuation done, with why its branch ended and the bifurcations found
    on it. False if the lease was lost (nothing is written)."""
    with db.transaction() as s:
        if not _JOBS.mark_done(s, cid, worker_id, spent_s, end_reason=end_reason,
                               criticality=criticality):
            return False
        s.execute(delete(Bifurcation).where(Bifurcation.continuation_id == cid))
        for i, bif in enumerate(bifurcations):
            s.execute(insert(Bifurcation).values(continuation_id=cid, idx=i, **bif))
    return True


# -- the faces' reads --

def points(db: Database, cid: int) -> list[RowMapping]:
    """The branch's points (without their resume state), in order."""
    return _JOBS.points(db, cid, POINT_COLUMNS)


def bifurcations(db: Database, cid: int) -> list[RowMapping]:
    """The bifurcations found on a finished continuation's branch, in branch order."""
    with db.sessions() as s:
        return [r._mapping for r in s.execute(
            select(*Bifurcation.__table__.columns).where(Bifurcation.continuation_id == cid)
            .order_by(Bifurcation.idx)).all()]
