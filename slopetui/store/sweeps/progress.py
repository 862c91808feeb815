"""The reads behind the progress of sweeps, each in one session (one snapshot of the
store). ``slopetui.sweeps.progress`` turns them into what the faces show; a sweep's
diagram is read by ``slopetui.store.diagrams``.
"""

from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass
from datetime import datetime, timedelta

from sqlalchemy import func, select

from slopetui.store.database import Database
from slopetui.store.models import Run, Sweep


@dataclass(frozen=True)
class SweepTallies:
    """The sweeps (newest first) and their runs counted, as of ``now`` (database time).

    counts   : runs per status, per sweep (a sweep without runs: absent)
    cached   : done runs that took an earlier result, per sweep
    inferred : inferred runs of adaptive sweeps, per sweep
    recent   : computed runs finished since ``since``, and the earliest start among them
    lifetime : computed runs finished, the earliest start and the latest finish among them,
               for the sweeps that have no run queued or running
    """

    now: datetime
    since: datetime
    sweeps: list[Sweep]
    counts: dict[int, dict[str, int]]
    cached: dict[int, int]
    inferred: dict[int, int]
    recent: dict[int, tuple[int, datetime | None]]
    lifetime: dict[int, tuple[int, datetime | None, datetime | None]]


def sweep_tallies(db: Database, sweep_ids: list[int] | None, rate_window: timedelta) -> SweepTallies:
    """The given sweeps (None or []: all) with their counts, in one session; ``recent``
    covers the ``rate_window`` before now."""
    with db.sessions() as s:
        now = db.now(s)
        q = select(Sweep).order_by(Sweep.id.desc())
        if sweep_ids:
            q = q.where(Sweep.id.in_(sweep_ids))
        sweeps = list(s.scalars(q))
        ids = [sw.id for sw in sweeps]
        counts: dict[int, dict[str, int]] = defaultdict(dict)
        for sid, status, n in s.execute(select(Run.sweep_id, Run.status, func.count())
                                        .where(Run.sweep_id.in_(ids))
                                        .group_by(Run.sweep_id, Run.status)):
            counts[sid][status] = n
        cached = dict(s.execute(select(Run.sweep_id, func.count())
                                .where(Run.sweep_id.in_(ids), Run.cached_from.is_not(None))
                                .group_by(Run.sweep_id)).all())
        adaptive = [sw.id for sw in sweeps if sw.adaptive_levels is not None]
        inferred = dict(s.execute(select(Run.sweep_id, func.count())
                                  .where(Run.sweep_id.in_(adaptive), Run.inferred.is_(True))
                                  .group_by(Run.sweep_id)).all()) if adaptive else {}
        since = now - rate_window
        computed = (Run.sweep_id.in_(ids), Run.status == "done", Run.cached_from.is_(None),
                    Run.inferred.is_(False))
        recent = {sid: (n, first) for sid, n, first in s.execute(
            select(Run.sweep_id, func.count(), func.min(Run.started_at))
            .where(*computed, Run.finished_at >= since)
            .group_by(Run.sweep_id))}
        # only the sweeps with nothing queued or running: a full read of their done runs
        idle = [sid for sid in ids
                if not (counts.get(sid, {}).get("queued") or counts.get(sid, {}).get("running"))]
        lifetime = {sid: (n, first, last) for sid, n, first, last in s.execute(
            select(Run.sweep_id, func.count(), func.min(Run.started_at),
                   func.max(Run.finished_at))
            .where(*computed, Run.sweep_id.in_(idle)).group_by(Run.sweep_id))} if idle else {}
    return SweepTallies(now, since, sweeps, counts, cached, inferred, recent, lifetime)


def running_runs(db: Database) -> tuple[int, int]:
    """How many runs are running, and how many of them a worker has begun (started_at
    set): the others were claimed in a batch and wait their turn in it (started_at NULL,
    ``store.claims``)."""
    with db.sessions() as s:
        held, begun = s.execute(select(func.count(), func.count(Run.started_at))
                                .where(Run.status == "running")).one()
    return held, begun


def active_sweep_ids(db: Database) -> set[int]:
    """The ids of the sweeps that are active now."""
    with db.sessions() as s:
        return set(s.scalars(select(Sweep.id).where(Sweep.status == "active")))
