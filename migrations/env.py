"""Alembic environment: runs on the connection of the slopetui Database being opened."""

from __future__ import annotations

from alembic import context

from slopetui.store.models import Base

config = context.config
database = config.attributes["database"]

with database.engine.connect() as connection:
    context.configure(
        connection=connection,
        target_metadata=Base.metadata,
        # SQLite cannot ALTER most things: Alembic rebuilds the table instead.
        render_as_batch=database.is_sqlite,
        compare_type=True,
    )
    with context.begin_transaction():
        context.run_migrations()
