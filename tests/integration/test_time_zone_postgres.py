"""On a PostgreSQL server whose time zone is not UTC, the times a store writes are still
UTC: its sessions run in UTC (slopetui.store.database), so the created_at defaults
(CURRENT_TIMESTAMP into "timestamp without time zone") agree with the times written from
db_time and with what the notebooks' DataFrames label UTC."""

from __future__ import annotations

from datetime import UTC, datetime, timedelta

from sqlalchemy import text

from slopetui.store.database import Database
from slopetui.store.open import open_store
from slopetui.sweeps.frames import sweeps_frame
from tests.support import submit_quick


def test_created_at_is_utc_on_a_server_in_another_zone(pg_server):
    with pg_server.database() as url:
        admin = Database(url)
        name = admin.url.database
        with admin.engine.connect() as conn:  # new sessions of this database: UTC+14
            conn.execution_options(isolation_level="AUTOCOMMIT").exec_driver_sql(
                f"ALTER DATABASE \"{name}\" SET TimeZone = 'Pacific/Kiritimati'")
        admin.dispose()
        db = open_store(url)
        with db.engine.connect() as conn:
            assert conn.execute(text("SHOW TimeZone")).scalar() == "UTC"
        submit_quick(db, 2)
        created = sweeps_frame(db)["created_at"].iloc[0].to_pydatetime()
        assert abs(created - datetime.now(UTC)) < timedelta(minutes=5)
        db.dispose()
