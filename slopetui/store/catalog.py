"""What the store holds: its tables and views with their columns (the SQL console's schema
tree). No UI; works on any engine, the read-only one included."""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from sqlalchemy import Engine

#: One column: (name, type as the database names it, part of the primary key).
Column = tuple[str, str, bool]


def tables_and_columns(engine: Engine) -> list[tuple[str, list[Column]]]:
    """The tables (sorted), then the views (sorted), each with its columns in order."""
    from sqlalchemy import inspect

    inspector = inspect(engine)
    names = sorted(inspector.get_table_names()) + sorted(inspector.get_view_names())
    return [(name, [(c["name"], str(c["type"]), bool(c.get("primary_key")))
                    for c in inspector.get_columns(name)]) for name in names]
