"""The statements of a two-parameter curve's life as a job (slopetui.queue.curve_jobs holds
the policy): submit, claim, save a point, finish, fail, release, heartbeat, requeue; and the
faces' reads of curves, their points and their codimension-two points. Each function is one
transaction.

The lease and its statements are every point-by-point job's (slopetui.store.jobs.point_jobs),
as for continuations: a curve's points are counted in ``n_points``, and a point is saved only
as the next one. What is a curve's own: the codimension-two points written with its finish.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from sqlalchemy import delete, insert, select

from slopetui.store.database import Database
from slopetui.store.jobs.point_jobs import LeasedRow, PointJobs, columns, record_of
from slopetui.store.models import Curve, CurveBifurcation, CurvePoint


@dataclass(frozen=True, slots=True)
class CurveRow(LeasedRow):
    """A curve's row (slopetui.store.models.Curve): what was asked, its place in the queue
    (LeasedRow) and its result so far."""

    kind: str
    param: str
    param2: str
    a: float
    b: float
    c: float
    d: float
    k: float
    v: float
    tau: float
    delta: float
    dt: float
    end_value: float
    max_points: int
    max_step: float
    hopf_branch: int
    branch_end: float | None
    engine: str
    end_reason: str | None
    n_points: int


@dataclass(frozen=True, slots=True)
class CurvePointRow:
    """A point of a curve as the faces read it (slopetui.store.models.CurvePoint, without
    what a resumption needs); multipliers as [re, im] pairs."""

    idx: int
    first: float
    second: float
    period: float
    amplitude: float | None
    l1: float | None
    curvature: float | None
    multipliers: list[list[float]] | None
    flow_index: int | None
    translation: float | None
    newton_steps: int | None


@dataclass(frozen=True, slots=True)
class SavedCurvePointRow(CurvePointRow):
    """A saved point with what a resumption needs: the step tried after it, and its
    resume state as float64 little-endian bytes (core.curve_start.SavedCurvePoint)."""

    step: float | None
    state: bytes | None


@dataclass(frozen=True, slots=True)
class CurveBifurcationRow:
    """A codimension-two point found on a finished curve (models.CurveBifurcation)."""

    idx: int
    type: str
    first: float
    second: float
    period: float
    note: str


_JOBS = PointJobs(Curve, CurvePoint, parent="curve_id", counter="n_points",
                  row=CurveRow, point_row=CurvePointRow, saved_row=SavedCurvePointRow)

#: The curves' lease (slopetui.store.jobs.leases): heartbeat and requeue.
lease = _JOBS.lease
# The statements every point-by-point job shares (slopetui.store.jobs.point_jobs), by the
# names the queue and the faces call: a curve's id is the job id.
submit = _JOBS.submit
claim = _JOBS.claim
#: Every saved point of a curve, with its resume state, in order.
saved_points = _JOBS.saved_points
#: The curve's points as the faces read them (without their resume state), in order.
points = _JOBS.points
#: Append a point (PointJobs.save_point), naming the engine of the worker that computed it.
save_point = _JOBS.save_point
fail = _JOBS.fail
release = _JOBS.release
status_counts = _JOBS.status_counts
held = _JOBS.held
#: Every curve, newest first; one curve's row (None: no such id).
curves = _JOBS.newest_first
curve = _JOBS.row


def finish(db: Database, cid: int, worker_id: str, end_reason: str, spent_s: float,
           found: Sequence[Mapping[str, Any]], engine: str | None = None) -> bool:
    """Mark a held curve done, with why it ended and the codimension-two points found on
    it by a worker of ``engine``. False if the lease was lost (nothing is written)."""
    with db.transaction() as s:
        if not _JOBS.mark_done(s, cid, worker_id, spent_s, engine, end_reason=end_reason):
            return False
        s.execute(delete(CurveBifurcation).where(CurveBifurcation.curve_id == cid))
        for i, point in enumerate(found):
            s.execute(insert(CurveBifurcation).values(curve_id=cid, idx=i, **point))
    return True


def bifurcations(db: Database, cid: int) -> list[CurveBifurcationRow]:
    """The codimension-two points found on a finished curve, in curve order."""
    with db.sessions() as s:
        return [record_of(CurveBifurcationRow, r) for r in s.execute(
            select(*columns(CurveBifurcation, CurveBifurcationRow))
            .where(CurveBifurcation.curve_id == cid).order_by(CurveBifurcation.idx)).all()]
