"""The reads behind a sweep's diagram and the progress of sweeps, each in one session (one
snapshot of the store). ``slopetui.sweeps.diagram`` and ``slopetui.sweeps.progress`` turn
them into what the faces draw.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from datetime import datetime, timedelta
from typing import Any, Generic, TypeVar

from sqlalchemy import func, select

from slopetui.store.database import Database
from slopetui.store.models import Run, Sweep

S = TypeVar("S")


@dataclass(frozen=True)
class DiagramRows(Generic[S]):
    """A sweep and its runs as a diagram reads them.

    rows : per run in grid order (iy, then ix): id, ix, iy, x (its x parameter), y (its y
           parameter; iy for a 1-D sweep), status, regime, peaks, drift, error, detail,
           period_count, lambda_max, lambda_err, inferred.
    """

    sweep_id: int
    name: str
    spec: S
    rows: Sequence[Sequence[Any]]


def diagram_rows(db: Database, sweep_id: int,
                 read_spec: Callable[[dict[str, Any]], tuple[S, str, str | None]]
                 ) -> DiagramRows[S] | None:
    """The sweep and its runs in one read; None if there is no such sweep. ``read_spec``
    turns the stored spec into the caller's spec and the names of its x and y parameters
    (y None for a 1-D sweep): the columns read depend on them."""
    with db.sessions() as s:
        sweep = s.get(Sweep, sweep_id)
        if sweep is None:
            return None
        spec, x_param, y_param = read_spec(sweep.spec)
        cols = (Run.id, Run.ix, Run.iy, getattr(Run, x_param),
                getattr(Run, y_param) if y_param else Run.iy, Run.status, Run.regime,
                Run.peaks, Run.drift, Run.error, Run.detail, Run.period_count, Run.lambda_max,
                Run.lambda_err, Run.inferred, Run.attractor, Run.flags,
                Run.maxima_per_period, Run.settled, Run.ic, Run.delta, Run.history)
        rows = s.execute(select(*cols).where(Run.sweep_id == sweep_id)
                         .order_by(Run.ic, Run.iy, Run.ix)).all()
    return DiagramRows(sweep.id, sweep.name, spec, rows)


@dataclass(frozen=True)
class SweepTallies:
    """The sweeps (newest first) and their runs counted, as of ``now`` (database time).

    counts   : runs per status, per sweep (a sweep without runs: absent)
    cached   : done runs that took an earlier result, per sweep
    inferred : inferred runs of adaptive sweeps, per sweep
    recent   : computed runs finished since ``since``, and the earliest start among them
    """

    now: datetime
    since: datetime
    sweeps: list[Sweep]
    counts: dict[int, dict[str, int]]
    cached: dict[int, int]
    inferred: dict[int, int]
    recent: dict[int, tuple[int, datetime | None]]


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
        recent = {sid: (n, first) for sid, n, first in s.execute(
            select(Run.sweep_id, func.count(), func.min(Run.started_at))
            .where(Run.sweep_id.in_(ids), Run.status == "done", Run.cached_from.is_(None),
                   Run.inferred.is_(False), Run.finished_at >= since)
            .group_by(Run.sweep_id))}
    return SweepTallies(now, since, sweeps, counts, cached, inferred, recent)


def active_sweep_ids(db: Database) -> set[int]:
    """The ids of the sweeps that are active now."""
    with db.sessions() as s:
        return set(s.scalars(select(Sweep.id).where(Sweep.status == "active")))
