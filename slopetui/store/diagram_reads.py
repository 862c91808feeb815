"""The read behind a sweep's diagram: the whole sweep, or only what changed since an
earlier read (``slopetui.sweeps.live_diagram`` keeps a diagram up to date with the
latter, ``slopetui.sweeps.diagram`` reads whole ones). What it returns, and which columns,
is ``diagram_rows``'s, shared with ``sqlite_diagram_reads``, the same whole read of a
SQLite file without SQLAlchemy (``slopetui show``).

*What changed* is found by two keys. New runs: an id above the highest one read before (a
sweep's runs, an adaptive sweep's next level and its inferred runs, are inserted under the
sweep's lock, one transaction after the other). Finished runs: ``finished_at`` at or
after a time the caller gives, which it takes from the ``now`` of its previous read minus
a margin. Both timestamps come from the database's clock (``db_time``), never a worker's,
so hosts whose clocks disagree cannot hide a result; the margin covers a result stamped
before one read and committed after it. Every other change to a run (a cancel, a resume,
a lease given back) is not found this way, and need not be guessed at: the same read
counts the sweep's runs per status, and a copy whose counts differ missed something and
reads the whole sweep again.

*One snapshot* for the runs, the counts and ``now``, or the counts could disagree with the
rows for runs that finished in between. SQLite's deferred BEGIN (``Database.sessions``)
holds one from the first statement on, in WAL mode; PostgreSQL's default READ COMMITTED
takes one per statement, so the session asks for REPEATABLE READ there.
"""

from __future__ import annotations

from collections.abc import Callable
from datetime import datetime
from typing import Any

from sqlalchemy import func, select
from sqlalchemy.sql.elements import ColumnElement

from slopetui.store.database import Database
from slopetui.store.diagram_rows import DiagramRead, S, run_columns
from slopetui.store.models import Run, Sweep


def diagram_columns(x_param: str, y_param: str | None,
                    drawn_only: bool = False) -> list[ColumnElement[Any]]:
    """The run columns of a diagram of the plane (x_param, y_param), named as
    ``diagram_rows.run_columns`` says (x and y first), and last finished_at: with the
    status, what tells a copy (``sweeps.live_diagram``) that a run it holds changed."""
    return [getattr(Run, x_param).label("x"),
            (getattr(Run, y_param) if y_param else Run.iy).label("y"),
            *(getattr(Run, name) for name in run_columns(y_param, drawn_only)),
            Run.finished_at]


def read_diagram(db: Database, sweep_id: int,
                 read_spec: Callable[[dict[str, Any]], tuple[S, str, str | None]], *,
                 after_id: int = 0, finished_since: datetime | None = None,
                 drawn_only: bool = False) -> DiagramRead[S] | None:
    """The sweep and, in one snapshot, its runs with an id above ``after_id`` or finished
    at or after ``finished_since`` (the defaults: every run); None if there is no such
    sweep. ``read_spec`` turns the stored spec into the caller's spec and the names of its
    x and y parameters (y None for a 1-D sweep): the columns read depend on them, and on
    ``drawn_only`` (``diagram_rows.run_columns``)."""
    with db.sessions() as s:
        if not db.is_sqlite:  # one snapshot for every statement (module docstring)
            s.connection(execution_options={"isolation_level": "REPEATABLE READ"})
        now = db.now(s)
        sweep = s.get(Sweep, sweep_id)
        if sweep is None:
            return None
        spec, x_param, y_param = read_spec(sweep.spec)
        changed = Run.id > after_id
        if finished_since is not None:
            changed = changed | (Run.finished_at >= finished_since)
        result = s.connection().execute(
            select(*diagram_columns(x_param, y_param, drawn_only))
            .where(Run.sweep_id == sweep_id, changed)
            .order_by(Run.ic, Run.iy, Run.ix))
        columns, rows = tuple(result.keys()), result.all()
        statuses = {status: n for status, n in s.execute(
            select(Run.status, func.count()).where(Run.sweep_id == sweep_id)
            .group_by(Run.status))}
        max_id = s.scalar(select(func.max(Run.id)).where(Run.sweep_id == sweep_id)) or 0
    return DiagramRead(sweep.id, sweep.name, spec, now, columns, rows, statuses, max_id)
