"""What is left in the queue, by what a worker can do about it: the reads behind a pool's
decision to leave (slopetui.queue.idle_exit). The runs' part is read here; the queue's
registry of job kinds adds every other kind's (slopetui.queue.registry.backlog).

A run is claimable when it is queued in an active sweep; a queued run of a paused sweep
waits for a resume, which may come at any moment. A running run (or continuation, or
hysteresis sweep) is not claimable, but it may come back to the queue if its worker dies,
and an adaptive sweep queues its next level when the last run of a level is done.
"""

from __future__ import annotations

from dataclasses import dataclass

from sqlalchemy import func, select

from slopetui.store.database import Database
from slopetui.store.models import Run, Sweep


@dataclass(frozen=True)
class Backlog:
    """Counts of the jobs left: runs, continuations and hysteresis sweeps together."""

    #: Queued runs of active sweeps, queued continuations and hysteresis sweeps.
    claimable: int
    #: Running runs, continuations and hysteresis sweeps (on any host).
    running: int
    #: Queued runs of paused sweeps.
    paused: int

    @property
    def idle(self) -> bool:
        """Nothing to claim and nothing running: no worker has anything to do now."""
        return self.claimable == 0 and self.running == 0

    @property
    def drained(self) -> bool:
        """Idle, and no paused sweep holds queued runs either: nothing left at all."""
        return self.idle and self.paused == 0


def run_backlog(db: Database) -> Backlog:
    """The runs' part of the queue's backlog, read now."""
    with db.sessions() as s:
        rows = s.execute(select(Run.status, Sweep.status, func.count())
                         .join(Sweep, Sweep.id == Run.sweep_id)
                         .where(Run.status.in_(("queued", "running")))
                         .group_by(Run.status, Sweep.status)).all()
    claimable = running = paused = 0
    for run_status, sweep_status, n in rows:
        if run_status == "running":
            running += n
        elif sweep_status == "active":
            claimable += n
        elif sweep_status == "paused":
            paused += n
    return Backlog(claimable=claimable, running=running, paused=paused)
