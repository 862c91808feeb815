"""Alembic, configured in code: the scripts in ``migrations/`` (shipped as a package, so a
non-editable install carries them), applied when a database is opened."""

from __future__ import annotations

import hashlib
from functools import lru_cache
from pathlib import Path

from alembic import command
from alembic.config import Config
from alembic.runtime.migration import MigrationContext
from alembic.script import ScriptDirectory
from filelock import FileLock
from platformdirs import user_cache_path

import migrations
from slopetui.store.database import Database, StoreError

#: How long a process waits for another one that is migrating the same database (s).
LOCK_TIMEOUT_S = 300


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
    with db.reader.connect() as conn:
        return MigrationContext.configure(conn).get_current_revision()


def _lock_path(db: Database) -> Path:
    """A lock beside a SQLite file, or in the user cache for a server URL."""
    if db.path is not None:
        return db.path.with_name(db.path.name + ".migrate.lock")
    key = hashlib.sha256(db.display_url.encode()).hexdigest()[:16]
    folder = user_cache_path("slopetui")
    folder.mkdir(parents=True, exist_ok=True)
    return folder / f"migrate-{key}.lock"


def upgrade(db: Database) -> tuple[str | None, str]:
    """Upgrade to head under the lock; returns (revision before, revision after)."""
    with FileLock(_lock_path(db), timeout=LOCK_TIMEOUT_S, mode=0o600):
        before = current_revision(db)
        if before != head_revision():
            _check_known(before)
            command.upgrade(alembic_config(db), "head")
        return before, head_revision()


def _check_known(revision: str | None) -> None:
    if revision is None:
        return
    script = ScriptDirectory(str(Path(migrations.__file__).parent))
    if revision not in {s.revision for s in script.walk_revisions()}:
        raise StoreError(f"the database is at schema revision {revision}, which this "
                         f"slopetui does not know: it was written by a newer slopetui")


def upgrade_on_open(db: Database) -> None:
    """The fast path checks the revision without the lock; only a stale schema locks."""
    if current_revision(db) != head_revision():
        upgrade(db)
