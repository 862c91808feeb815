"""The reads behind the notebooks' DataFrames (``slopetui.sweeps.frames``): runs as rows of
plain values, column by column as the caller names them, and the sweeps' stored specs.

Rows of columns, not ORM objects: a sweep of 10 000 runs is read in one statement and
never builds 10 000 ``Run`` instances with their identity map and change tracking (the
figures are in ``slopetui.sweeps.frames``). The column types still apply: a ``Measure``
reads NULL back as NaN, ``peaks`` is a list, timestamps are ``datetime`` (naive, UTC).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from typing import Any

from sqlalchemy import Row, select

from slopetui.store.database import Database
from slopetui.store.models import Run, Sweep
from slopetui.store.sweeps.annotations import tagged


def run_rows(db: Database, columns: Sequence[str], *, sweep: int | None = None,
             regime: str | None = None, status: str | None = None, tag: str | None = None
             ) -> list[Row[Any]] | None:
    """The named columns of the runs with the given sweep id, status and regime, of a
    sweep with this tag (None: any), in grid order: by sweep, then as ``export`` writes a sweep (iy, then ix), then
    by initial condition. None if ``sweep`` names no stored sweep (checked in the same
    snapshot as the runs are read).

    ``regime`` matches a result: the done runs with that regime (computed or inferred),
    since a run that is not done has none yet.
    """
    unknown = [name for name in columns if name not in Run.__table__.c]
    if unknown:
        raise ValueError(f"runs has no column {unknown[0]!r}")
    query = select(*(Run.__table__.c[name] for name in columns))
    if sweep is not None:
        query = query.where(Run.sweep_id == sweep)
    if status is not None:
        query = query.where(Run.status == status)
    if regime is not None:
        query = query.where(Run.regime == regime, Run.status == "done")
    if tag is not None:
        query = query.where(Run.sweep_id.in_(tagged(tag)))
    query = query.order_by(Run.sweep_id, Run.iy, Run.ix, Run.ic)
    # a Core connection, not a Session: the ORM's row loading took as long as the read
    with db.read() as conn:  # one transaction: one snapshot for both reads
        known = sweep is None or conn.execute(select(Sweep.id).where(Sweep.id == sweep)).first()
        return list(conn.execute(query).all()) if known else None


def sweep_specs(db: Database, sweep_ids: Iterable[int]) -> dict[int, dict[str, Any]]:
    """The stored spec of each of these sweeps (as submitted: axes, fixed parameters,
    solver settings), by id; a sweep that is not stored is absent."""
    ids = list(sweep_ids)
    specs: dict[int, dict[str, Any]] = {}
    with db.sessions() as s:
        for i in range(0, len(ids), 500):  # stay under SQLite's bound-parameter limit
            specs.update((sweep_id, spec) for sweep_id, spec in s.execute(
                select(Sweep.id, Sweep.spec).where(Sweep.id.in_(ids[i:i + 500]))))
    return specs
