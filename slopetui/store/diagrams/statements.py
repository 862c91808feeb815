"""The statements of a sweep's diagram read, in plain SQL with named parameters
(``:sweep_id``): one text for the two reads, ``reads`` (SQLAlchemy's ``text``, on
SQLite and PostgreSQL alike, the models' column types decoding the values) and
``sqlite_reads`` (the standard library's sqlite3, for ``slopetui show``). No
SQLAlchemy here, so that the latter loads none.
"""

from __future__ import annotations

from collections.abc import Sequence

from core.params import PARAM_NAMES

#: The newest sweep's id (NULL without sweeps).
NEWEST_SWEEP = "SELECT max(id) FROM sweeps"
#: The sweep itself: its spec is JSON (text on SQLite).
SWEEP = "SELECT id, name, spec FROM sweeps WHERE id = :sweep_id"
#: The sweep's runs per status: every run, whichever rows a read takes.
STATUSES = "SELECT status, count(*) FROM runs WHERE sweep_id = :sweep_id GROUP BY status"
#: The sweep's highest run id (NULL without runs).
MAX_RUN_ID = "SELECT max(id) FROM runs WHERE sweep_id = :sweep_id"


def runs_sql(x_param: str, y_param: str | None, columns: Sequence[str], *,
             after_id: bool = False, finished_since: bool = False) -> str:
    """The sweep's runs in grid order (ic, iy, ix): the sweep's parameters as ``x`` and
    ``y`` (a 1-D sweep's y is its iy), then ``columns``. ``after_id``: only the runs with
    an id above ``:after_id``, or with ``finished_since`` also those finished at or after
    ``:finished_since``."""
    for param in (x_param, y_param or "iy"):  # named into the SQL text: a column for sure
        if param not in (*PARAM_NAMES, "iy"):
            raise ValueError(f"{param!r} is not a parameter of a run")
    where = "sweep_id = :sweep_id"
    if after_id and finished_since:
        where += " AND (id > :after_id OR finished_at >= :finished_since)"
    elif after_id:
        where += " AND id > :after_id"
    return (f"SELECT {x_param} AS x, {y_param or 'iy'} AS y, {', '.join(columns)} "
            f"FROM runs WHERE {where} ORDER BY ic, iy, ix")
