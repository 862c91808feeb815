"""The statements of a hysteresis sweep's life as a job (slopetui.queue.hysteresis_jobs
holds the policy): submit, claim, save a point, finish, fail, release, heartbeat, requeue;
and the faces' reads of the sweeps and their points. Each function is one transaction.

The lease and its statements are every point-by-point job's (slopetui.store.job_leases),
as for continuations (branch_rows): a sweep's points are counted in ``n_done``, and a
point is saved only as the next one. What is a sweep's own: its finish, with where each
branch changes regime.
"""

from __future__ import annotations

from collections.abc import Mapping

from sqlalchemy import RowMapping

from slopetui.store.database import Database
from slopetui.store.job_leases import JobLeases
from slopetui.store.models import HysteresisPoint, HysteresisSweep

#: A hysteresis sweep's row by column name (a read-only mapping).
HysteresisRow = RowMapping

#: Columns of a point the faces read (all but the state handed over).
POINT_COLUMNS = ("idx", "direction", "value", "regime", "detail", "amplitude", "growth",
                 "jumped")

_JOBS = JobLeases(HysteresisSweep, HysteresisPoint, parent="sweep_id", counter="n_done")

# The statements every point-by-point job shares (slopetui.store.job_leases), by the names
# the queue and the faces call: a sweep's id is the job id.
submit = _JOBS.submit
claim = _JOBS.claim
#: Every saved point of a sweep, with the state it hands over, in order.
saved_points = _JOBS.saved_points
save_point = _JOBS.save_point
fail = _JOBS.fail
release = _JOBS.release
heartbeat = _JOBS.heartbeat
requeue_expired = _JOBS.requeue_expired
requeue_worker = _JOBS.requeue_worker
status_counts = _JOBS.status_counts
held = _JOBS.held
#: Every hysteresis sweep, newest first; one sweep's row (None: no such id).
hysteresis_sweeps = _JOBS.newest_first
hysteresis_sweep = _JOBS.row


#: A finished sweep's results: where each branch changes regime, refined, and its bracket.
TRANSITION_COLUMNS = ("onset_up", "onset_up_before", "onset_up_after", "offset_down",
                      "offset_down_before", "offset_down_after")


def finish(db: Database, sid: int, worker_id: str, transitions: Mapping[str, float | None],
           spent_s: float) -> bool:
    """Mark a held sweep done, with where each branch changes regime (TRANSITION_COLUMNS,
    each given). False if the lease was lost (nothing is written)."""
    with db.transaction() as s:
        return _JOBS.mark_done(s, sid, worker_id, spent_s,
                               **{name: transitions[name] for name in TRANSITION_COLUMNS})


# -- the faces' reads --

def points(db: Database, sid: int) -> list[RowMapping]:
    """The sweep's points (without the state they hand over), in order."""
    return _JOBS.points(db, sid, POINT_COLUMNS)
