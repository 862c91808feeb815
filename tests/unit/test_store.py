"""The store in one process: migrations, SQLite settings, NaN and infinity, permissions (from
other processes and a plain install: tests/integration/test_store_processes.py).

The schema and the values run on SQLite and PostgreSQL (``store``); the tests marked
``sqlite_only`` are about SQLite's file itself (PRAGMAs, its locks, file permissions)."""

from __future__ import annotations

import math
import sqlite3
import stat

import pytest
from alembic.autogenerate import compare_metadata
from alembic.runtime.migration import MigrationContext
from sqlalchemy import inspect, select, text, update

from slopetui.store.migrate import current_revision, head_revision
from slopetui.store.models import Base, Run
from tests.support import submit_quick


def test_the_fast_revision_check_knows_the_head(store):
    import migrations
    assert migrations.HEAD == head_revision() == store.stored_revision() == current_revision(store)


def test_models_and_migrations_agree(store):
    with store.engine.connect() as conn:
        ctx = MigrationContext.configure(conn, opts={"compare_type": True})
        assert compare_metadata(ctx, Base.metadata) == []


def test_constraints_and_indexes_are_named(store):
    insp = inspect(store.engine)
    names = [ix["name"] for ix in insp.get_indexes("runs")]
    names += [ck["name"] for ck in insp.get_check_constraints("runs")]
    assert names and all(n and n.startswith(("ix_runs_", "ck_runs_")) for n in names)


@pytest.mark.sqlite_only
def test_sqlite_settings(db):
    with db.engine.connect() as conn:
        assert conn.exec_driver_sql("PRAGMA journal_mode").scalar() == "wal"
        assert conn.exec_driver_sql("PRAGMA foreign_keys").scalar() == 1
        assert conn.exec_driver_sql("PRAGMA busy_timeout").scalar() >= 10_000


@pytest.mark.sqlite_only
def test_writes_take_the_write_lock_at_begin(db):
    """BEGIN IMMEDIATE: a transaction that has not written yet already excludes other
    writers (a deferred BEGIN would not, and its later lock upgrade can deadlock)."""
    other = sqlite3.connect(db.path, timeout=0, isolation_level=None)
    with db.transaction() as s:
        s.execute(text("SELECT 1"))
        with pytest.raises(sqlite3.OperationalError, match="locked"):
            other.execute("BEGIN IMMEDIATE")
    other.execute("BEGIN IMMEDIATE")  # free again after commit
    other.execute("ROLLBACK")


@pytest.mark.sqlite_only
def test_a_new_database_is_readable_by_its_owner_only(db):
    submit_quick(db, 2)  # a write, so that the -wal file exists
    for path in (db.path, db.path.with_name(db.path.name + "-wal")):
        assert stat.S_IMODE(path.stat().st_mode) == 0o600, path


def test_nan_and_infinity_round_trip(store):
    sub = submit_quick(store, 1)
    with store.transaction() as s:
        s.execute(update(Run).where(Run.sweep_id == sub.sweep_id).values(
            status="done", regime="complex", lambda_max=math.nan, amplitude=math.inf,
            drift=-math.inf, period=1.5, peaks=[1.0, 2.0]))
    with store.sessions() as s:
        run = s.scalars(select(Run)).one()
        assert math.isnan(run.lambda_max) and run.amplitude == math.inf
        assert run.drift == -math.inf and run.period == 1.5 and run.peaks == [1.0, 2.0]
        # In SQL, infinity is a float and NaN (NULL on both backends: slopetui.store
        # .column_types.Measure) never compares true; PostgreSQL's own NaN would.
        raw = s.execute(text("SELECT amplitude > 1e308, lambda_max > 0, lambda_max <= 0 "
                             "FROM runs")).one()
        assert tuple(raw) == (1, None, None)  # PostgreSQL's true == 1
        typeof = "typeof(amplitude)" if store.is_sqlite else "pg_typeof(amplitude)::text"
        assert s.execute(text(f"SELECT {typeof} FROM runs")).scalar() == \
            ("real" if store.is_sqlite else "double precision")


@pytest.mark.sqlite_only
def test_reads_do_not_take_the_write_lock(db):
    """A status screen reading the store must not stall the workers' writes."""
    other = sqlite3.connect(db.path, timeout=0, isolation_level=None)
    with db.sessions() as s:
        s.execute(text("SELECT count(*) FROM runs")).scalar()
        other.execute("BEGIN IMMEDIATE")  # a writer gets in while the read is open
        other.execute("ROLLBACK")
