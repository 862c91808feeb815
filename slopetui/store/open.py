"""Opening a store for use: ``open_store(url)`` opens it (``Database``) and migrates it to
the current schema.

Migrating lives here rather than in ``Database``'s constructor so that the database module
does not import ``slopetui.store.migrate``, which imports ``Database`` (import-linter's
``database-before-migrations`` contract keeps that circle out), and so that opening
without migrating is an explicit choice: ``Database(url)`` alone, for the
tools that inspect or change an old schema and for workers whose pool migrated first.
"""

from __future__ import annotations

import migrations
from slopetui.store.database import Database
from slopetui.store.failures import StoreError


def open_store(url: str | None = None, *, upgrade: bool = True,
               read_only_ok: bool = False) -> Database:
    """The store at ``url`` (default: ``$SLOPETUI_DB``, else ``default_url()``), created if
    it is a new SQLite file, and migrated to the current schema.

    upgrade : apply pending migrations (under a file lock, after a backup copy of a SQLite
              file; ``slopetui.store.migrate``). False opens the store as it is.
    read_only_ok : the caller only reads: a SQLite file it cannot write is opened
              read-only (``Database.read_only`` says so) if its schema is current; one that
              would need migrating is refused, saying why.
    """
    db = Database(url, read_only_ok=read_only_ok)
    if upgrade and db.read_only is not None and db.opened_revision != migrations.HEAD:
        db.dispose()
        raise StoreError(f"cannot read {db.path}: its schema is at revision "
                         f"{db.opened_revision or 'none'}, not {migrations.HEAD} as this "
                         f"slopetui needs, and it cannot be migrated here ({db.unwritable})")
    if upgrade and db.opened_revision != migrations.HEAD:
        # only a stale schema pays for Alembic (~0.2 s to import) and the migration lock
        from slopetui.store.migrate import upgrade as upgrade_schema
        upgrade_schema(db)
    return db
