"""The statements of a hysteresis sweep's life as a job (slopetui.queue.hysteresis_jobs
holds the policy): submit, claim, save a point, finish, fail, release, heartbeat, requeue;
and the faces' reads of the sweeps and their points. Each function is one transaction.

The lease and its statements are every point-by-point job's (slopetui.store.jobs.point_jobs),
as for continuations (``continuations``): a sweep's points are counted in ``n_done``, and a
point is saved only as the next one. What is a sweep's own: its finish, with where each
branch changes regime.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from slopetui.store.database import Database
from slopetui.store.jobs.point_jobs import LeasedRow, PointJobs
from slopetui.store.models import HysteresisPoint, HysteresisSweep


@dataclass(frozen=True, slots=True)
class HysteresisRow(LeasedRow):
    """A hysteresis sweep's row (slopetui.store.models.HysteresisSweep): what was asked,
    its place in the queue (LeasedRow) and, once done, where each branch changes regime
    (TRANSITION_COLUMNS; None where it keeps its attractor)."""

    param: str
    start: float
    stop: float
    n_points: int
    a: float
    b: float
    c: float
    d: float
    k: float
    v: float
    tau: float
    delta: float
    dt: float
    t_settle: float
    window: float
    tol: float
    engine: str
    onset_up: float | None
    offset_down: float | None
    onset_up_before: float | None
    onset_up_after: float | None
    offset_down_before: float | None
    offset_down_after: float | None
    n_done: int


@dataclass(frozen=True, slots=True)
class HysteresisPointRow:
    """A point of a sweep as the faces read it (slopetui.store.models.HysteresisPoint,
    without the state it hands over); amplitude and growth None where undefined."""

    idx: int
    direction: str
    value: float
    regime: str
    detail: str
    amplitude: float | None
    growth: float | None
    jumped: bool


@dataclass(frozen=True, slots=True)
class SavedHysteresisPoint(HysteresisPointRow):
    """A saved point with the state it hands over (5 x (N + 1) float64 little-endian
    bytes; None: its run left the finite range, nothing to hand over)."""

    state: bytes | None


_JOBS = PointJobs(HysteresisSweep, HysteresisPoint, parent="sweep_id", counter="n_done",
                  row=HysteresisRow, point_row=HysteresisPointRow,
                  saved_row=SavedHysteresisPoint)

#: The hysteresis sweeps' lease (slopetui.store.jobs.leases): heartbeat and requeue.
lease = _JOBS.lease
# The statements every point-by-point job shares (slopetui.store.jobs.point_jobs), by the names
# the queue and the faces call: a sweep's id is the job id.
submit = _JOBS.submit
claim = _JOBS.claim
#: Every saved point of a sweep, with the state it hands over, in order.
saved_points = _JOBS.saved_points
#: The sweep's points as the faces read them (without the state they hand over), in order.
points = _JOBS.points
#: Append a point (PointJobs.save_point), naming the engine of the worker that computed it.
save_point = _JOBS.save_point
fail = _JOBS.fail
release = _JOBS.release
status_counts = _JOBS.status_counts
held = _JOBS.held
#: Every hysteresis sweep, newest first; one sweep's row (None: no such id).
hysteresis_sweeps = _JOBS.newest_first
hysteresis_sweep = _JOBS.row


#: A finished sweep's results: where each branch changes regime, refined, and its bracket.
TRANSITION_COLUMNS = ("onset_up", "onset_up_before", "onset_up_after", "offset_down",
                      "offset_down_before", "offset_down_after")


def finish(db: Database, sid: int, worker_id: str, transitions: Mapping[str, float | None],
           spent_s: float, engine: str | None = None) -> bool:
    """Mark a held sweep done, with where each branch changes regime (TRANSITION_COLUMNS,
    each given), refined by a worker of ``engine`` (the digest it computes with; "mixed"
    once workers of different engines saved its points). False if the lease was lost
    (nothing is written)."""
    with db.transaction() as s:
        return _JOBS.mark_done(s, sid, worker_id, spent_s, engine,
                               **{name: transitions[name] for name in TRANSITION_COLUMNS})
