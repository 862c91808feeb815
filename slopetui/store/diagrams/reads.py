"""The read behind a sweep's diagram: the whole sweep, or only what changed since an
earlier read (``slopetui.sweeps.live_diagram`` keeps a diagram up to date with the
latter, ``slopetui.sweeps.diagram`` reads whole ones). What it returns, and which columns,
is ``result``'s, shared with ``sqlite_reads``, the same whole read of a
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

from collections.abc import Callable, Sequence
from datetime import datetime
from typing import Any

from sqlalchemy import BindParameter, Table, TextualSelect, bindparam, column, text

from slopetui.store.database import Database
from slopetui.store.diagrams import statements
from slopetui.store.diagrams.result import DiagramRead, S, run_columns
from slopetui.store.models import Run, Sweep

#: The tables read, with the column types that decode their values.
runs_table: Table = Run.__table__  # type: ignore[assignment]
sweeps: Table = Sweep.__table__  # type: ignore[assignment]


def diagram_columns(x_param: str, y_param: str | None, drawn_only: bool = False) -> list[str]:
    """The run columns of a diagram of the plane (x_param, y_param), as
    ``result.run_columns`` names them (x and y excluded), and last finished_at:
    with the status, what tells a copy (``sweeps.live_diagram``) that a run it holds
    changed."""
    return [*run_columns(y_param, drawn_only), "finished_at"]


def typed(sql: str, table: Table, names: Sequence[tuple[str, str]],
          *binds: BindParameter[Any]) -> TextualSelect:
    """``sql`` whose result columns (each a name, and the column of ``table`` whose type
    decodes it) come back as the models give them, as a select of the models' columns
    does: Boolean as bool, JSON parsed, a Measure's NULL as NaN. ``binds``: parameters
    given a type (a datetime, as the column stores it)."""
    return text(sql).bindparams(*binds).columns(
        *(column(name, table.c[source].type) for name, source in names))


def read_diagram(db: Database, sweep_id: int,
                 read_spec: Callable[[dict[str, Any]], tuple[S, str, str | None]], *,
                 after_id: int = 0, finished_since: datetime | None = None,
                 drawn_only: bool = False) -> DiagramRead[S] | None:
    """The sweep and, in one snapshot, its runs with an id above ``after_id`` or finished
    at or after ``finished_since`` (the defaults: every run); None if there is no such
    sweep. ``read_spec`` turns the stored spec into the caller's spec and the names of its
    x and y parameters (y None for a 1-D sweep): the columns read depend on them, and on
    ``drawn_only`` (``result.run_columns``). The statements are ``statements``'s."""
    params: dict[str, Any] = {"sweep_id": sweep_id}
    with db.sessions() as s:
        if not db.is_sqlite:  # one snapshot for every statement (module docstring)
            s.connection(execution_options={"isolation_level": "REPEATABLE READ"})
        now = db.now(s)
        conn = s.connection()
        sweep = conn.execute(typed(statements.SWEEP, sweeps,
                                   [(n, n) for n in ("id", "name", "spec")]), params).first()
        if sweep is None:
            return None
        spec, x_param, y_param = read_spec(sweep.spec)
        names = diagram_columns(x_param, y_param, drawn_only)
        since = () if finished_since is None else (
            bindparam("finished_since", type_=runs_table.c.finished_at.type),)
        runs = typed(statements.runs_sql(x_param, y_param, names, after_id=True,
                                          finished_since=finished_since is not None),
                     runs_table, [("x", x_param), ("y", y_param or "iy"),
                                  *((n, n) for n in names)], *since)
        given = {} if finished_since is None else {"finished_since": finished_since}
        result = conn.execute(runs, {**params, "after_id": after_id, **given})
        columns, rows = tuple(result.keys()), result.all()
        statuses = {status: n for status, n in conn.execute(text(statements.STATUSES), params)}
        max_id = conn.execute(text(statements.MAX_RUN_ID), params).scalar() or 0
    return DiagramRead(sweep.id, sweep.name, spec, now, columns, rows, statuses, max_id)
