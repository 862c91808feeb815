"""The statements of an adaptive sweep's refinement (``slopetui.sweeps.adaptive`` holds the
refinement itself and the reasons for each decision).

*One transaction, re-checked inside.* ``advance_if_ready`` opens one ``db.transaction()``
(BEGIN IMMEDIATE on SQLite, the sweep's row locked FOR UPDATE on PostgreSQL), re-reads
there whether the sweep's current level is complete, and only then hands the locked sweep
to the caller's step: two workers that both see a level complete queue the next one once.
Everything the step reads and writes (``LockedSweep``) is in that same transaction.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from sqlalchemy import exists, insert, select
from sqlalchemy.orm import Session

from slopetui.store.database import Database
from slopetui.store.models import Run, Sweep
from slopetui.store.sweeps.writes import RunRow, insert_runs

#: A level is complete when none of its runs is in one of these.
UNFINISHED = ("queued", "running")
#: Adaptive sweeps whose current level is complete: the cheap check of advance_all (one
#: indexed query, well under a millisecond, when there is nothing to do).
_READY = (select(Sweep.id)
          .where(Sweep.adaptive_levels.is_not(None), Sweep.refined.is_(False),
                 Sweep.status == "active",
                 ~exists().where(Run.sweep_id == Sweep.id, Run.status.in_(UNFINISHED)))
          .order_by(Sweep.id))


def ready_sweeps(db: Database) -> list[int]:
    """Adaptive sweeps that are active, not refined, and have no run queued or running."""
    with db.read() as conn:
        return list(conn.execute(_READY).scalars())


class LockedSweep:
    """An adaptive sweep whose row is locked by the transaction advance_if_ready opened,
    with the reads and writes a refinement step makes in it."""

    def __init__(self, session: Session, sweep: Sweep) -> None:
        self._s, self._sweep = session, sweep

    @property
    def id(self) -> int:
        return self._sweep.id

    @property
    def spec(self) -> dict[str, Any]:
        """The sweep's stored spec (``SweepSpec.to_dict``)."""
        return self._sweep.spec

    @property
    def levels(self) -> int:
        """Its number of refinement levels (``[adaptive] levels``)."""
        assert self._sweep.adaptive_levels is not None  # advance_if_ready checked
        return self._sweep.adaptive_levels

    @property
    def level(self) -> int:
        """The level queued last."""
        assert self._sweep.level is not None  # advance_if_ready checked
        return self._sweep.level

    @level.setter
    def level(self, level: int) -> None:
        self._sweep.level = level

    def mark_refined(self) -> None:
        """Refinement is over: every lattice point has its run."""
        self._sweep.refined = True

    def finished_runs(self) -> list[tuple[int, int, str, str | None]]:
        """(ix, iy, status, regime) of every computed run of the sweep that finished (done
        or failed); inferred runs are not among them."""
        rows = self._s.execute(select(Run.ix, Run.iy, Run.status, Run.regime)
                               .where(Run.sweep_id == self.id,
                                      Run.status.in_(("done", "failed")),
                                      Run.inferred.is_(False)))
        return [(ix, iy, status, regime) for ix, iy, status, regime in rows]

    def insert_runs(self, rows: list[RunRow]) -> int:
        """Insert new runs, the cache answering those it can (``writes.insert_runs``,
        which completes the rows in place); returns how many took a cached result."""
        return insert_runs(self._s, self.id, rows)

    def insert_inferred(self, rows: list[RunRow]) -> None:
        """Insert complete rows of inferred runs as they are (no cache: nothing computes
        them)."""
        self._s.execute(insert(Run), rows)


def advance_if_ready(db: Database, sweep_id: int, step: Callable[[LockedSweep], int]) -> int:
    """In one write transaction: lock the sweep, and if it is an active, unrefined adaptive
    sweep whose current level has no run queued or running, return ``step(sweep)``; else
    0 without calling it. What the step changes commits with the transaction, or not at
    all if it raises."""
    with db.transaction() as s:
        sweep = s.get(Sweep, sweep_id, with_for_update=True)
        if (sweep is None or sweep.adaptive_levels is None or sweep.refined
                or sweep.status != "active" or sweep.level is None):
            return 0
        if s.scalar(select(exists().where(Run.sweep_id == sweep_id,
                                          Run.status.in_(UNFINISHED)))):
            return 0
        return step(LockedSweep(s, sweep))
