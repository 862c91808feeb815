"""The statements the faces (the CLI, the application, the report) read the store with,
each behind a name: the faces call these and import no SQLAlchemy (import-linter's
``faces-no-sqlalchemy`` contract), the way Optuna's RDB storage owns every query.

Reads only, on ``Database.sessions()``. What belongs to a sweeps-level concept (a
diagram, the progress of a sweep, pause/resume/cancel) is read and written by the
modules of the store named after it (``sweeps``, ``diagrams``), which
``slopetui.sweeps`` calls; the queue's statements are in ``runs``, ``jobs`` and
``workers``.
"""

from __future__ import annotations

from collections.abc import Generator, Iterable
from datetime import datetime

from sqlalchemy import Engine, func, select

from slopetui.store.database import Database
from slopetui.store.models import Run, Sweep
from slopetui.store.sweeps.annotations import tagged

__all__ = ["Engine", "database_now", "newest_sweep_id", "run_by_id", "runs_matching", "runs_of",
           "runtime_total", "sweep_engines", "sweep_exists", "sweep_status", "unfinished_runs"]

# ``Engine`` is named here for the faces' annotations (the SQL console's read-only engine),
# so that they need not import SQLAlchemy to spell it.


def runs_matching(db: Database, *, sweep: int | None = None, regime: str | None = None,
                  status: str | None = None, tag: str | None = None,
                  limit: int | None = None) -> list[Run]:
    """The runs with the given sweep id, regime and status, of a sweep with this tag
    (None: any), newest first; at most ``limit`` of them (None or 0: all). ``slopetui
    runs``."""
    query = select(Run).order_by(Run.id.desc())
    for column, value in (("sweep_id", sweep), ("regime", regime), ("status", status)):
        if value is not None:
            query = query.where(getattr(Run, column) == value)
    if tag is not None:
        query = query.where(Run.sweep_id.in_(tagged(tag)))
    if limit:
        query = query.limit(limit)
    with db.sessions() as s:
        return list(s.scalars(query))


def run_by_id(db: Database, run_id: int) -> Run | None:
    """The run with this id (its columns loaded, the session closed), or None if the store
    has no such run. The run detail's copy of a run (``slopetui.sweeps.recompute``)."""
    with db.sessions() as s:
        return s.get(Run, run_id)


def sweep_engines(db: Database, sweep_id: int) -> tuple[str, ...]:
    """The engine digests the sweep's done runs were computed with, sorted (one, unless
    the engine changed while the sweep was computed; none before a run is done). An
    inferred run (an adaptive sweep's, never computed) names no engine: its column is the
    queue-time digest. What a sweep's figure names as its engine
    (``slopetui.figures.figure_facts``)."""
    with db.sessions() as s:
        return tuple(s.scalars(select(Run.engine).distinct()
                               .where(Run.sweep_id == sweep_id, Run.status == "done",
                                      Run.inferred.is_(False))
                               .order_by(Run.engine)))


def sweep_exists(db: Database, sweep_id: int) -> bool:
    """Whether the store has a sweep with this id."""
    with db.sessions() as s:
        return s.get(Sweep, sweep_id) is not None


def sweep_status(db: Database, sweep_id: int) -> str | None:
    """The sweep's stored status (active, paused, cancelled), None if there is no such
    sweep."""
    with db.sessions() as s:
        return s.scalar(select(Sweep.status).where(Sweep.id == sweep_id))


def runs_of(db: Database, sweep_id: int) -> Generator[Run, None, None]:
    """The sweep's runs in grid order (row by row: iy, then ix); none for an unknown
    sweep (ask sweep_exists first). The session stays open while they are read: the
    caller iterates to the end (or closes the iterator). ``slopetui export``."""
    with db.sessions() as s:
        yield from s.scalars(select(Run).where(Run.sweep_id == sweep_id)
                             .order_by(Run.iy, Run.ix))


def newest_sweep_id(db: Database) -> int | None:
    """The highest sweep id (the sweep submitted last); None if there is no sweep."""
    with db.sessions() as s:
        return s.scalar(select(func.max(Sweep.id)))


def database_now(db: Database) -> datetime:
    """The database's clock (UTC), the one leases, heartbeats and run timestamps use."""
    with db.sessions() as s:
        return db.now(s)


def unfinished_runs(db: Database, sweep_ids: Iterable[int]) -> int:
    """How many runs of these sweeps are not done (queued, running, failed, cancelled)."""
    query = (select(func.count()).select_from(Run)
             .where(Run.sweep_id.in_(list(sweep_ids)), Run.status != "done"))
    with db.sessions() as s:
        return s.scalar(query) or 0


def runtime_total(db: Database, sweep_ids: Iterable[int]) -> float:
    """The sum of the runtimes (s) of these sweeps' runs, 0 if none has one. A run copied
    from the cache carries the runtime of the run that computed it."""
    with db.sessions() as s:
        total = s.scalar(select(func.sum(Run.runtime_s)).where(Run.sweep_id.in_(list(sweep_ids))))
    return float(total or 0.0)
