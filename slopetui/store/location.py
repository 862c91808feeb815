"""Where the store is when no ``--db`` is given. Light on purpose (no SQLAlchemy), so that
``slopetui --help`` can name the default without loading a database driver."""

from __future__ import annotations

import os

from platformdirs import user_data_path

#: Environment variable that selects the database (any SQLAlchemy URL).
DB_ENV = "SLOPETUI_DB"
#: Environment variable naming a PostgreSQL role's URL that only reads the same database:
#: ``slopetui sql`` and the application's console run their queries under it
#: (slopetui.store.database.Database.read_only_engine; docs/store.md).
READ_DB_ENV = "SLOPETUI_READ_DB"


def default_url() -> str:
    """$SLOPETUI_DB, or SQLite in the user data folder (~/.local/share/slopetui on Linux)."""
    env = os.environ.get(DB_ENV)
    if env:
        return env
    return f"sqlite:///{user_data_path('slopetui') / 'slopetui.db'}"
