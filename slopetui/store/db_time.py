"""Database time as a SQL expression, in UTC, to the millisecond.

Leases, heartbeats and run timestamps are stamped by the database, not by the worker's
clock, so workers on hosts whose clocks disagree still agree on when a lease expired.
SQLAlchemy's ``func.now()`` is CURRENT_TIMESTAMP on SQLite: whole seconds only, too
coarse for runs that take milliseconds.
"""

from __future__ import annotations

from datetime import datetime
from typing import Any

from sqlalchemy import DateTime
from sqlalchemy.ext.compiler import compiles
from sqlalchemy.sql.functions import FunctionElement


class db_now(FunctionElement[datetime]):
    type = DateTime()
    inherit_cache = True


@compiles(db_now)
def _default(_element: db_now, _compiler: Any, **_kw: Any) -> str:
    return "CURRENT_TIMESTAMP"


@compiles(db_now, "sqlite")
def _sqlite(_element: db_now, _compiler: Any, **_kw: Any) -> str:
    return "strftime('%Y-%m-%d %H:%M:%f', 'now')"


@compiles(db_now, "postgresql")
def _postgresql(_element: db_now, _compiler: Any, **_kw: Any) -> str:
    # the columns are timestamp without time zone: store UTC, whatever the session's zone
    return "(statement_timestamp() AT TIME ZONE 'UTC')"
