"""Alembic, configured in code: the scripts in ``migrations/`` (shipped as a package, so a
non-editable install carries them), applied when a database is opened
(``slopetui.store.open.open_store``).

Every change of schema, up or down, first copies a SQLite store aside
(``slopetui.db.bak-<revision before>``); a downgrade of a PostgreSQL store first dumps it
(pg_dump, ``slopetui.store.server_dump``), or is refused unless told to go without. A
downgrade's prompt names what it drops (``plan_downgrade``). Every change runs with
SQLite's foreign keys off: Alembic's batch mode rebuilds a table by copy, DROP and
rename, and with foreign keys on, the DROP of ``sweeps`` cascades to ``runs`` (a
downgrade of 0002 deleted every run that way).
``PRAGMA foreign_key_check`` then runs inside the migration's transaction, and a
violation rolls the whole migration back.

Two processes must not migrate one database at once. A SQLite file is reached from one
host only, so a file lock beside it serialises them. A PostgreSQL database is shared by
hosts whose file systems differ: there the lock is the server's own, a session advisory
lock (four simultaneous `slopetui db upgrade` from four hosts, each with a lock file of
its own, raced: two failed with a duplicate key on pg_type_typname_nsp_index, as in
optuna#1092).
"""

from __future__ import annotations

import hashlib
import os
import sqlite3
from collections.abc import Iterator
from contextlib import AbstractContextManager, closing, contextmanager
from dataclasses import dataclass
from datetime import datetime
from functools import lru_cache
from pathlib import Path
from urllib.parse import quote

from alembic import command
from alembic.config import Config
from alembic.runtime.migration import MigrationContext
from alembic.script import ScriptDirectory
from filelock import FileLock
from platformdirs import user_cache_path
from sqlalchemy import Connection
from sqlalchemy.exc import OperationalError

import migrations
from slopetui.store.database import Database
from slopetui.store.downgrade_losses import losses, sentence
from slopetui.store.failures import StoreError, describe
from slopetui.store.server_dump import dump

#: How long a process waits for another one that is migrating the same database (s).
LOCK_TIMEOUT_S = 300
#: The key of PostgreSQL's advisory lock around migrations (one bigint, per database):
#: the first 8 bytes of sha256("slopetui.migrate"), so that it collides with no other
#: application's lock on a shared database by accident.
ADVISORY_KEY = int.from_bytes(hashlib.sha256(b"slopetui.migrate").digest()[:8], "big",
                              signed=True)


def alembic_config(db: Database) -> Config:
    cfg = Config()
    cfg.set_main_option("script_location", str(Path(migrations.__file__).parent))
    cfg.set_main_option("sqlalchemy.url", db.url.render_as_string(hide_password=False)
                        .replace("%", "%%"))
    cfg.attributes["database"] = db
    return cfg


@lru_cache(maxsize=1)
def head_revision() -> str:
    script = ScriptDirectory(str(Path(migrations.__file__).parent))
    head = script.get_current_head()
    assert head is not None, "migrations/versions holds no revision"
    return head


def current_revision(db: Database) -> str | None:
    with db.read() as conn:
        return MigrationContext.configure(conn).get_current_revision()


def _lock_path(db: Database) -> Path:
    """A lock beside a SQLite file, or in the user cache for a server URL."""
    if db.path is not None:
        return db.path.with_name(db.path.name + ".migrate.lock")
    key = hashlib.sha256(db.display_url.encode()).hexdigest()[:16]
    folder = user_cache_path("slopetui")
    folder.mkdir(parents=True, exist_ok=True)
    return folder / f"migrate-{key}.lock"


@contextmanager
def _advisory_lock(db: Database) -> Iterator[None]:
    """PostgreSQL's session advisory lock ADVISORY_KEY, held on a connection of its own
    (in autocommit: no transaction stays open beside the migration's) until the block
    ends; waits up to LOCK_TIMEOUT_S for another holder."""
    with db.engine.connect().execution_options(isolation_level="AUTOCOMMIT") as conn:
        conn.exec_driver_sql(f"SET lock_timeout = '{LOCK_TIMEOUT_S}s'")
        try:
            conn.exec_driver_sql(f"SELECT pg_advisory_lock({ADVISORY_KEY})")
        except OperationalError as exc:  # lock_timeout: SQLSTATE 55P03
            raise StoreError(f"another process has been migrating {db.display_url} for "
                             f"{LOCK_TIMEOUT_S} s; try again when it is done") from exc
        try:
            yield
        finally:
            conn.exec_driver_sql(f"SELECT pg_advisory_unlock({ADVISORY_KEY})")


def migration_lock(db: Database) -> AbstractContextManager[object]:
    """The lock that one migration of ``db`` holds (see the module docstring)."""
    if db.url.get_backend_name() == "postgresql":
        return _advisory_lock(db)
    return FileLock(_lock_path(db), timeout=LOCK_TIMEOUT_S, mode=0o600)


def upgrade(db: Database) -> tuple[str | None, str]:
    """Upgrade to head under the lock; returns (revision before, revision after)."""
    with db.failures_translated(), migration_lock(db):
        before = current_revision(db)
        if before != head_revision():
            _check_known(before)
            backup_copy(db, before)
            command.upgrade(alembic_config(db), "head")
        return before, head_revision()


@dataclass(frozen=True)
class DowngradePlan:
    """A downgrade before it runs: the revisions it goes between, and what it drops (see
    slopetui.store.downgrade_losses), counted when planned."""

    before: str
    after: str
    drops: list[str]

    @property
    def dropped(self) -> str:
        """"3 continuations (412 branch points) and 2 hysteresis sweeps"."""
        return sentence(self.drops)


def _older(db: Database, revision: str) -> str:
    """The database's revision, if ``revision`` is older (or "base"); else StoreError."""
    known = revisions()
    if revision != "base" and revision not in known:
        raise StoreError(f"REV: unknown revision {revision!r}; one of "
                         f"{', '.join(known)} or base")
    before = current_revision(db)
    _check_known(before)
    if before is None or (revision != "base"
                          and known.index(revision) >= known.index(before)):
        raise StoreError(f"REV: {revision} is not older than the database's revision "
                         f"{before or 'none (empty)'}")
    return before


def plan_downgrade(db: Database, revision: str) -> DowngradePlan:
    """What a downgrade of ``db`` to ``revision`` would drop, counted now; StoreError for a
    revision that is not older than the database's."""
    before = _older(db, revision)
    known = revisions()
    first = 0 if revision == "base" else known.index(revision) + 1
    undone = list(reversed(known[first:known.index(before) + 1]))
    return DowngradePlan(before, revision, losses(db, undone, to_base=revision == "base"))


def downgrade(db: Database, revision: str, *, backup: bool = True,
              backup_folder: Path | None = None) -> tuple[str | None, str, Path | None]:
    """Downgrade to ``revision`` (an older one, or "base": no tables at all) under the
    lock, after a backup: a SQLite file is always copied aside (backup_copy); a
    PostgreSQL database is dumped with pg_dump into ``backup_folder`` (default
    slopetui.store.server_dump.backup_folder()) unless ``backup`` is false, and without
    pg_dump the downgrade is refused. Returns (revision before, revision after, the
    backup)."""
    with db.failures_translated(), migration_lock(db):
        before = _older(db, revision)
        if db.is_sqlite:
            copy = backup_copy(db, before)
        elif backup:
            copy = dump(db, before, backup_folder)
        else:
            copy = None
        command.downgrade(alembic_config(db), revision)
        return before, revision, copy


@lru_cache(maxsize=1)
def revisions() -> list[str]:
    """Every revision, oldest first."""
    script = ScriptDirectory(str(Path(migrations.__file__).parent))
    return [s.revision for s in reversed(list(script.walk_revisions()))]


def _check_known(revision: str | None) -> None:
    if revision is not None and revision not in revisions():
        raise StoreError(f"the database is at schema revision {revision}, which this "
                         f"slopetui does not know: it was written by a newer slopetui")


def backup_copy(db: Database, revision: str | None) -> Path | None:
    """Copy a SQLite store aside before its schema changes, as ``<file>.bak-<revision>``
    (never over an older copy: then ``.bak-<revision>-<time>``), readable by its owner
    only. None for a new (empty) store or a server database (a downgrade dumps that
    with pg_dump: slopetui.store.server_dump). SQLite's backup API copies a consistent state, the WAL included."""
    if db.path is None or revision is None:
        return None
    target = db.path.with_name(f"{db.path.name}.bak-{revision}")
    if target.exists():
        stamp = datetime.now().strftime("%Y%m%dT%H%M%S%f")
        target = target.with_name(f"{target.name}-{stamp}")
    try:
        os.close(os.open(target, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o600))
        source = sqlite3.connect(f"file:{quote(str(db.path))}?mode=ro", uri=True)
        with closing(source), closing(sqlite3.connect(target)) as copy:
            source.backup(copy)
    except (OSError, sqlite3.Error) as exc:
        target.unlink(missing_ok=True)
        raise StoreError(f"the schema was not changed: the backup copy {target} could not "
                         f"be written ({describe(target, str(exc))})") from None
    return target


@contextmanager
def foreign_keys_off(connection: Connection, db: Database) -> Iterator[None]:
    """SQLite's foreign keys off for a migration on ``connection`` (see the module
    docstring), on again after it. The pragma is a no-op inside a transaction, so it is
    set on the driver's connection before Alembic begins one."""
    if not db.is_sqlite:
        yield
        return
    raw = connection.connection.driver_connection
    assert raw is not None  # a connection that is open has its driver's connection
    raw.execute("PRAGMA foreign_keys = OFF")
    try:
        yield
    finally:
        raw.execute("PRAGMA foreign_keys = ON")


def check_foreign_keys(connection: Connection, db: Database) -> None:
    """Inside the migration's transaction: refuse to commit rows whose foreign keys point
    nowhere (the exception rolls the migration back)."""
    if not db.is_sqlite:
        return  # PostgreSQL enforces foreign keys during DDL itself
    bad = connection.exec_driver_sql("PRAGMA foreign_key_check").fetchall()
    if bad:
        table, rowid, parent, _ = bad[0]
        raise StoreError(f"the migration was rolled back: it would leave {len(bad)} rows "
                         f"whose foreign keys point nowhere (first: {table} row {rowid} -> "
                         f"{parent})")
