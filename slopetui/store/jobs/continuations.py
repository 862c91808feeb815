"""The statements of a continuation's life as a job (slopetui.queue.branch_jobs holds the
policy): submit, claim, save a point, finish, fail, release, heartbeat, requeue; and the
faces' reads of continuations, their points and their bifurcations. Each function is one
transaction.

The lease and its statements are every point-by-point job's (slopetui.store.jobs.point_jobs):
a continuation's points are counted in ``n_points``, and a point is saved only as the
next one. What is a continuation's own: the Hopf point recorded with the first point, and
the bifurcations written with its finish.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from sqlalchemy import delete, insert, select

from slopetui.store.database import Database
from slopetui.store.jobs.point_jobs import LeasedRow, PointJobs, columns, record_of
from slopetui.store.models import Bifurcation, BranchPoint, Continuation


@dataclass(frozen=True, slots=True)
class ContinuationRow(LeasedRow):
    """A continuation's row (slopetui.store.models.Continuation): what was asked, its
    place in the queue (LeasedRow) and its result so far."""

    param: str
    start: str
    hopf_branch: int | None
    a: float
    b: float
    c: float
    d: float
    k: float
    v: float
    tau: float
    delta: float
    from_run: int | None
    dt: float
    end_value: float | None
    max_points: int
    max_step: float
    engine: str
    hopf_value: float | None
    hopf_period: float | None
    criticality: str | None
    l1: float | None
    end_reason: str | None
    n_points: int


@dataclass(frozen=True, slots=True)
class BranchPointRow:
    """A point of a branch as the faces read it (slopetui.store.models.BranchPoint,
    without what a resumption needs); multipliers as [re, im] pairs."""

    idx: int
    value: float
    period: float
    amplitude: float
    stable: bool
    unstable_count: int
    leading_re: float
    leading_im: float
    multipliers: list[list[float]]
    flow_index: int
    translation: float


@dataclass(frozen=True, slots=True)
class SavedBranchPoint(BranchPointRow):
    """A saved point with what a resumption needs: the step tried after it, and its
    unknowns and secant as float64 little-endian bytes (core.branch_start.SavedPoint)."""

    step: float
    state: bytes


@dataclass(frozen=True, slots=True)
class BifurcationRow:
    """A bifurcation found on a finished branch (slopetui.store.models.Bifurcation)."""

    idx: int
    type: str
    value: float
    period: float
    mu_re: float
    mu_im: float
    reason: str | None


_JOBS = PointJobs(Continuation, BranchPoint, parent="continuation_id", counter="n_points",
                  row=ContinuationRow, point_row=BranchPointRow, saved_row=SavedBranchPoint)

#: The continuations' lease (slopetui.store.jobs.leases): heartbeat and requeue.
lease = _JOBS.lease
# The statements every point-by-point job shares (slopetui.store.jobs.point_jobs), by the names
# the queue and the faces call: a continuation's id is the job id.
submit = _JOBS.submit
claim = _JOBS.claim
#: Every saved point of a continuation, with its resume state, in order.
saved_points = _JOBS.saved_points
#: The branch's points as the faces read them (without their resume state), in order.
points = _JOBS.points
fail = _JOBS.fail
release = _JOBS.release
status_counts = _JOBS.status_counts
held = _JOBS.held
#: Every continuation, newest first; one continuation's row (None: no such id).
continuations = _JOBS.newest_first
continuation = _JOBS.row


def save_point(db: Database, cid: int, worker_id: str, point: Mapping[str, Any],
               spent_s: float, hopf: tuple[float, float] | None = None, *,
               engine: str | None = None) -> bool:
    """Append ``point`` (its ``idx`` must be the next) to a continuation the worker holds,
    add ``spent_s`` to its compute time, name the worker's ``engine`` (the digest it
    computes with; "mixed" once workers of different engines saved points) and (first
    point from the Hopf point) record the Hopf point. False if the lease was lost or the
    point is not the next: nothing is written."""
    extra = {} if hopf is None else {"hopf_value": hopf[0], "hopf_period": hopf[1]}
    return _JOBS.save_point(db, cid, worker_id, point, spent_s, engine, **extra)


def finish(db: Database, cid: int, worker_id: str, end_reason: str, criticality: str | None,
           spent_s: float, bifurcations: Sequence[Mapping[str, Any]],
           engine: str | None = None, l1: float | None = None) -> bool:
    """Mark a held continuation done, with why its branch ended and the bifurcations found
    on it by a worker of ``engine`` (save_point). False if the lease was lost (nothing is
    written)."""
    with db.transaction() as s:
        if not _JOBS.mark_done(s, cid, worker_id, spent_s, engine, end_reason=end_reason,
                               criticality=criticality, l1=l1):
            return False
        s.execute(delete(Bifurcation).where(Bifurcation.continuation_id == cid))
        for i, bif in enumerate(bifurcations):
            s.execute(insert(Bifurcation).values(continuation_id=cid, idx=i, **bif))
    return True


# -- the faces' reads --

def bifurcations(db: Database, cid: int) -> list[BifurcationRow]:
    """The bifurcations found on a finished continuation's branch, in branch order."""
    with db.sessions() as s:
        return [record_of(BifurcationRow, r) for r in s.execute(
            select(*columns(Bifurcation, BifurcationRow))
            .where(Bifurcation.continuation_id == cid).order_by(Bifurcation.idx)).all()]
