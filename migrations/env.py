"""Alembic environment: runs on the connection of the slopetui Database being opened,
with SQLite's foreign keys off and checked before commit (why: slopetui.store.migrate)."""

from __future__ import annotations

from alembic import context

from slopetui.store.migrate import check_foreign_keys, foreign_keys_off
from slopetui.store.models import Base

config = context.config
database = config.attributes["database"]

with database.engine.connect() as connection, foreign_keys_off(connection, database):
    context.configure(
        connection=connection,
        target_metadata=Base.metadata,
        # SQLite cannot ALTER most things: Alembic rebuilds the table instead.
        render_as_batch=database.is_sqlite,
        compare_type=True,
        # One transaction for every step and the foreign key check: SQLite's DDL is
        # transactional, but Alembic assumes it is not and commits each revision alone.
        transactional_ddl=True,
    )
    with context.begin_transaction():
        context.run_migrations()
        check_foreign_keys(connection, database)
