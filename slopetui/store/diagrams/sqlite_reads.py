"""A sweep's whole diagram read from a SQLite file through the standard library's
sqlite3, without SQLAlchemy: what ``slopetui show`` draws. Importing SQLAlchemy
(0.18-0.21 s of CPU), its ORM (0.08-0.10 s) and the models with the store (0.06-0.08 s)
took a third of the ~1 s of CPU a `slopetui show` of benchmarks/bench_tui.py's 100 x 100
sweep used, and its rows another 0.05 s (process_time around each step, three fresh
processes; benchmarks/bench_startup.py times the whole command).

Only a store that needs nothing more than reading is read this way: a plain
``sqlite:///FILE`` URL (no driver other than pysqlite, no query options) naming a file
that exists, on a local disk, at the current schema (``migrations.HEAD``). It is opened
``mode=ro``, so this read can neither create the database nor change it (SQLite may make
the -wal and -shm files beside it, as for any reader of a WAL database). Anything else
raises ``NeedsDatabase``, and the caller opens the store with ``open_store`` as every
command does: there a new file is created, an old schema migrated (under its lock, after
a backup copy), a newer one refused, a network file system refused, a damaged file
named with its cause. So does any error of sqlite3 on the way (a damaged page, a lock
held longer than ``TIMEOUT_S``): the same read through ``Database`` then meets it again
and reports it as every command does.

The statements are ``reads.read_diagram``'s own (``statements``: its whole read,
without finished_at, which only a live copy needs), in one snapshot (a deferred BEGIN before the
first statement, as ``Database.sessions``; in WAL mode it reads beside the workers'
writes). Values come back as the models' column types give them: Boolean as bool, JSON
parsed, a Measure's NULL as NaN (``DECODE``); tests/unit/test_sqlite_diagram_reads.py
holds the two reads equal.
"""

from __future__ import annotations

import json
import math
import sqlite3
from collections.abc import Callable, Sequence
from contextlib import closing
from datetime import datetime
from pathlib import Path
from typing import Any
from urllib.parse import quote

import migrations
from core.mounts import network_filesystem
from slopetui.store.diagrams import statements
from slopetui.store.diagrams.result import DiagramRead, S, run_columns
from slopetui.store.id_lists import sqlite_file
from slopetui.store.location import default_url

#: The URL schemes read here: SQLite through Python's own driver (what ``Database`` uses
#: for them too). Another driver (SQLCipher, aiosqlite) goes through ``Database``.
SCHEMES = ("sqlite", "sqlite+pysqlite")
#: Seconds a statement waits for a lock. A reader in WAL mode waits for none but short
#: ones (another connection recovering the log after a crash, or removing it as it
#: closes); past this, ``Database`` (which waits a minute) reads instead.
TIMEOUT_S = 5.0
#: A run column whose stored value is not what the models give (the others are).
DECODE: dict[str, Callable[[Any], Any]] = {
    "inferred": lambda v: None if v is None else bool(v),          # Boolean: 0 or 1
    "settled": lambda v: None if v is None else bool(v),
    "certified": lambda v: None if v is None else bool(v),
    "peaks": lambda v: None if v is None else json.loads(v),       # JSON, as text
    "drift": lambda v: math.nan if v is None else float(v),       # Measure: NULL is NaN
    "lambda_max": lambda v: math.nan if v is None else float(v),
    "lambda_err": lambda v: math.nan if v is None else float(v),
}
#: Database time as ``db_time.db_now`` spells it on SQLite (UTC, to the millisecond).
NOW_SQL = "SELECT strftime('%Y-%m-%d %H:%M:%f', 'now')"


class NeedsDatabase(Exception):
    """This store is to be opened with ``open_store`` and read through ``Database``
    (the module docstring says when); the message says why."""


def read_sqlite_diagram(url: str | None, sweep_id: int | None,
                        read_spec: Callable[[dict[str, Any]], tuple[S, str, str | None]], *,
                        drawn_only: bool = False) -> DiagramRead[S] | None:
    """The sweep ``sweep_id`` (None: the newest) of the SQLite store at ``url`` (default:
    ``$SLOPETUI_DB``, else the default file) and all its runs, in one snapshot; None if
    there is no such sweep (or no sweep at all). ``read_spec`` and ``drawn_only`` as for
    ``reads.read_diagram``. Raises NeedsDatabase (module docstring)."""
    path = _plain_file(url or default_url())
    try:
        conn = sqlite3.connect(f"file:{quote(str(path))}?mode=ro", uri=True,
                               timeout=TIMEOUT_S, isolation_level=None)
        with closing(conn):
            conn.execute("BEGIN")  # one snapshot (module docstring)
            revision = conn.execute("SELECT version_num FROM alembic_version").fetchone()
            if revision is None or revision[0] != migrations.HEAD:
                raise NeedsDatabase(f"the store is at schema revision "
                                    f"{revision and revision[0]}, not {migrations.HEAD}")
            return _read(conn, sweep_id, read_spec, drawn_only)
    except sqlite3.Error as exc:  # no alembic_version (a new file) included
        raise NeedsDatabase(f"sqlite3: {exc}") from exc


def _plain_file(url: str) -> Path:
    """The file of a URL that this module reads; NeedsDatabase for any other."""
    scheme = url.partition("://")[0]
    if scheme not in SCHEMES or "?" in url:
        raise NeedsDatabase("not a plain sqlite:/// URL")
    path = sqlite_file(url)
    if path is None or not path.is_file():
        raise NeedsDatabase("no SQLite file there yet")
    if network_filesystem(path.parent) is not None:
        raise NeedsDatabase("a SQLite file on a network file system")
    return path


def _read(conn: sqlite3.Connection, sweep_id: int | None,
          read_spec: Callable[[dict[str, Any]], tuple[S, str, str | None]],
          drawn_only: bool) -> DiagramRead[S] | None:
    if sweep_id is None:
        sweep_id = conn.execute(statements.NEWEST_SWEEP).fetchone()[0]
        if sweep_id is None:
            return None
    params = {"sweep_id": sweep_id}
    (now,) = conn.execute(NOW_SQL).fetchone()
    sweep = conn.execute(statements.SWEEP, params).fetchone()
    if sweep is None:
        return None
    spec, x_param, y_param = read_spec(json.loads(sweep[2]))
    columns = ("x", "y", *run_columns(y_param, drawn_only))
    cursor = conn.execute(statements.runs_sql(x_param, y_param, columns[2:]), params)
    rows = _decoded(columns, cursor.fetchall())
    statuses = dict(conn.execute(statements.STATUSES, params).fetchall())
    max_id = conn.execute(statements.MAX_RUN_ID, params).fetchone()[0] or 0
    return DiagramRead(sweep[0], sweep[1], spec, datetime.fromisoformat(now), columns, rows,
                       statuses, max_id)


def _decoded(columns: Sequence[str], rows: list[tuple[Any, ...]]) -> list[tuple[Any, ...]]:
    """The rows with each value of a DECODE column decoded."""
    decode = [(i, DECODE[name]) for i, name in enumerate(columns) if name in DECODE]
    out = []
    for row in rows:
        values = list(row)
        for i, f in decode:
            values[i] = f(values[i])
        out.append(tuple(values))
    return out
