"""The id lists behind shell completion (``slopetui.cli.completion``): the sweeps' ids
with their names, and the newest runs' ids with their sweep and regime.

Completion runs in a fresh process on every <TAB>, so these reads must be quick and leave
no trace:

- A store is never created nor migrated: a SQLite file that does not exist, in-memory
  SQLite and a file on a network file system (which ``Database`` refuses) have no ids.
- A SQLite file is read through the standard library's ``sqlite3``, opened ``mode=ro``
  (it cannot create the file nor write to it). Not through ``Database``: importing
  SQLAlchemy alone takes ~0.25 s, most of completion's budget of 0.3 s a keystroke.
- Any other database (PostgreSQL) is opened with ``Database(url)``, which does not
  migrate, with a short connect timeout (an unreachable server must not freeze the
  shell), and disposed after.

The statements are plain SQL text, the one text for both paths (``:name`` parameters
are sqlite3's named style and SQLAlchemy's ``text()`` alike), so that the SQLite path
needs no SQLAlchemy to build them. They filter on the digits typed so far: with a
100 000-run store, ``--from-run 5<TAB>`` still finds the newest runs whose id starts
with 5, not only the newest 200 of all.
"""

from __future__ import annotations

import sqlite3
from pathlib import Path
from typing import Any
from urllib.parse import quote, unquote

from core.mounts import network_filesystem

#: How many ids a list holds at most: more is no help in a shell's menu, and the reads
#: stay a few milliseconds on a 100 000-run store.
SWEEP_LIMIT = 500
RUN_LIMIT = 200
#: Seconds to wait for a PostgreSQL server (libpq's connect_timeout) or a SQLite lock.
TIMEOUT_S = 2

SWEEPS_SQL = ("SELECT id, name FROM sweeps WHERE CAST(id AS TEXT) LIKE :pattern "
              "ORDER BY id DESC LIMIT :limit")
RUNS_SQL = ("SELECT id, sweep_id, regime, status FROM runs WHERE CAST(id AS TEXT) LIKE :pattern "
            "ORDER BY id DESC LIMIT :limit")


def sweep_ids(url: str, prefix: str = "", limit: int = SWEEP_LIMIT) -> list[tuple[int, str]]:
    """(id, name) of the sweeps whose id starts with ``prefix`` (digits), newest first.
    Empty for a store that does not exist (nothing is created); a damaged or foreign one
    raises (sqlite3.Error, SQLAlchemy's errors, StoreError)."""
    return [(int(i), str(name)) for i, name in _read(url, SWEEPS_SQL, prefix, limit)]


def newest_run_ids(url: str, prefix: str = "", limit: int = RUN_LIMIT
                   ) -> list[tuple[int, int, str | None, str]]:
    """(id, sweep id, regime or None, status) of the newest runs whose id starts with
    ``prefix`` (digits), newest first; as sweep_ids for a store that is not there."""
    return [(int(i), int(sweep), regime, str(status))
            for i, sweep, regime, status in _read(url, RUNS_SQL, prefix, limit)]


def _read(url: str, sql: str, prefix: str, limit: int) -> list[Any]:
    if not prefix.isdigit() and prefix != "":
        return []  # no id starts with it; isdigit also keeps LIKE's wildcards out
    params = {"pattern": prefix + "%", "limit": limit}
    backend = url.partition("://")[0].split("+")[0]
    if backend == "sqlite":
        path = sqlite_file(url)
        if path is None or not path.is_file() or network_filesystem(path.parent) is not None:
            return []
        conn = sqlite3.connect(f"file:{quote(str(path))}?mode=ro", uri=True, timeout=TIMEOUT_S)
        try:
            return conn.execute(sql, params).fetchall()
        finally:
            conn.close()
    return _read_other(url, sql, params)


def _read_other(url: str, sql: str, params: dict[str, Any]) -> list[Any]:
    """The statement on a database other than SQLite, through Database (not migrated)."""
    from sqlalchemy import text

    from slopetui.store.database import Database, parse_url

    parsed = parse_url(url)
    if parsed.get_backend_name() == "postgresql" and "connect_timeout" not in parsed.query:
        parsed = parsed.update_query_dict({"connect_timeout": str(TIMEOUT_S)})
    db = Database(parsed.render_as_string(hide_password=False))
    try:
        with db.read() as conn:
            return list(conn.execute(text(sql), params).all())
    finally:
        db.dispose()


def sqlite_file(url: str) -> Path | None:
    """The file of a SQLite URL as ``slopetui.store.database.sqlite_path`` reads it
    (``sqlite:///relative.db``, ``sqlite:////absolute.db``, ``~`` expanded, %-escapes
    decoded, ``?query`` dropped), without SQLAlchemy; None for in-memory SQLite."""
    rest = url.partition("://")[2].split("?", 1)[0]
    _host, slash, database = rest.partition("/")
    database = unquote(database)
    if not slash or database in ("", ":memory:"):
        return None
    return Path(database).expanduser().resolve()
