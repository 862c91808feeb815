"""A PostgreSQL store's backup before a downgrade: ``pg_dump`` of the whole database into
a file readable by its owner only, as a SQLite store is copied aside
(``slopetui.store.migrate.backup_copy``). Restore it into a new, empty database with
``psql -v ON_ERROR_STOP=1 -d NEW -f FILE``.

The password never reaches a command line (``ps`` shows every process's arguments to
every user): pg_dump reads it from PGPASSWORD in its own environment. The rest of the
connection (host, port, user, database, the URL's options such as sslmode) goes as a
connection string in ``--dbname``, which holds nothing secret.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
from datetime import datetime
from pathlib import Path

from platformdirs import user_data_path

from slopetui.store.database import Database
from slopetui.store.failures import StoreError
from slopetui.store.pg_programs import PG_BIN_GLOBS, distribution_folders

#: What to do without pg_dump, in the words of the message that refuses.
NO_PG_DUMP = ("install PostgreSQL's client programs (Debian/Ubuntu: sudo apt install "
              "postgresql-client; conda install -c conda-forge postgresql), or pass "
              "--no-backup to downgrade without a backup")


def backup_folder() -> Path:
    """Where the dumps go: beside the default store (~/.local/share/slopetui/backups)."""
    return user_data_path("slopetui") / "backups"


def find_pg_dump() -> Path:
    """PATH's pg_dump, else the newest of /usr/lib/postgresql/*/bin and the like (a newer
    pg_dump dumps an older server; an older one refuses a newer server)."""
    on_path = shutil.which("pg_dump")
    if on_path:
        return Path(on_path)
    for folder in distribution_folders():
        if os.access(folder / "pg_dump", os.X_OK):
            return folder / "pg_dump"
    raise StoreError(f"the schema was not changed: no pg_dump on PATH or in "
                     f"{PG_BIN_GLOBS[0]} to back the database up first: {NO_PG_DUMP}")


def _conninfo_value(value: str) -> str:
    return "'" + value.replace("\\", "\\\\").replace("'", "\\'") + "'"


def connection(db: Database) -> tuple[str, dict[str, str]]:
    """libpq's connection string for ``db`` without its password, and the environment
    that carries the password (PGPASSWORD; empty without one)."""
    url = db.url
    given: dict[str, object] = {"host": url.host, "port": url.port, "user": url.username,
                                "dbname": url.database}
    fields = {key: str(value) for key, value in given.items() if value is not None}
    password = None if url.password is None else str(url.password)
    for key, value in url.query.items():
        text = ",".join(value) if isinstance(value, tuple) else value
        if key == "password":
            password = text
        else:
            fields[key] = text
    conninfo = " ".join(f"{key}={_conninfo_value(value)}" for key, value in fields.items())
    return conninfo, ({} if password is None else {"PGPASSWORD": password})


def _target(folder: Path, db: Database, revision: str) -> Path:
    """``<host>-<port>-<database>.bak-<revision>.sql``, never over an older dump (then
    with the time after it, as SQLite's copies)."""
    url = db.url
    stem = re.sub(r"[^A-Za-z0-9._-]", "_",
                  f"{url.host or 'local'}-{url.port or 5432}-{url.database or 'postgres'}")
    target = folder / f"{stem}.bak-{revision}.sql"
    if target.exists():
        stamp = datetime.now().strftime("%Y%m%dT%H%M%S%f")
        target = folder / f"{stem}.bak-{revision}-{stamp}.sql"
    return target


def dump(db: Database, revision: str, folder: Path | None = None) -> Path:
    """pg_dump ``db`` (at schema ``revision``) into a new file of mode 600 in ``folder``
    (default ``backup_folder()``, made with mode 700); its path. StoreError, and no file
    left, if pg_dump is missing or fails."""
    if db.url.get_backend_name() != "postgresql":
        raise StoreError(f"the schema was not changed: slopetui backs up SQLite and "
                         f"PostgreSQL stores, not {db.url.get_backend_name()}: back it up "
                         "yourself, then pass --no-backup")
    program = find_pg_dump()
    folder = backup_folder() if folder is None else folder
    target = _target(folder, db, revision)
    conninfo, secret = connection(db)
    try:
        folder.mkdir(mode=0o700, parents=True, exist_ok=True)
        fd = os.open(target, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o600)
    except OSError as exc:
        raise StoreError(f"the schema was not changed: the backup {target} could not be "
                         f"created ({exc.strerror})") from None
    try:
        with os.fdopen(fd, "wb") as out:
            done = subprocess.run(
                [str(program), "--format=plain", "--no-password", f"--dbname={conninfo}"],
                stdout=out, stderr=subprocess.PIPE, env={**os.environ, **secret},
                check=False)
    except OSError as exc:
        target.unlink(missing_ok=True)
        raise StoreError(f"the schema was not changed: {program} could not run "
                         f"({exc.strerror})") from None
    if done.returncode != 0:
        target.unlink(missing_ok=True)
        why = done.stderr.decode(errors="replace").strip().splitlines() or ["no message"]
        raise StoreError(f"the schema was not changed: pg_dump failed ({why[-1]}); fix it, "
                         "or pass --no-backup to downgrade without a backup")
    return target
