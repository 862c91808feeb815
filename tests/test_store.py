"""The store: migrations, SQLite settings, NaN and infinity, permissions, packaging."""

from __future__ import annotations

import math
import multiprocessing as mp
import os
import sqlite3
import stat
import subprocess
import sys
from pathlib import Path

import pytest
from alembic.autogenerate import compare_metadata
from alembic.runtime.migration import MigrationContext
from sqlalchemy import inspect, select, text, update

from slopetui.store import Base, Database, Run
from slopetui.store.migrate import current_revision, head_revision
from tests.conftest import slopetui_cli, submit_quick

ROOT = Path(__file__).resolve().parents[1]


def test_an_empty_database_upgrades_to_head(db_url):
    db = Database(db_url, upgrade=False)
    assert current_revision(db) is None
    assert slopetui_cli("db", "upgrade", "--db", db_url).returncode == 0
    assert current_revision(db) == head_revision()
    assert {"sweeps", "runs", "workers", "alembic_version"} <= set(inspect(db.engine).get_table_names())
    again = slopetui_cli("db", "upgrade", "--db", db_url)
    assert "already at" in again.stdout


def test_the_fast_revision_check_knows_the_head(db):
    import migrations
    assert migrations.HEAD == head_revision() == db.stored_revision() == current_revision(db)


def test_models_and_migrations_agree(db):
    with db.engine.connect() as conn:
        ctx = MigrationContext.configure(conn, opts={"compare_type": True})
        assert compare_metadata(ctx, Base.metadata) == []


def test_constraints_and_indexes_are_named(db):
    insp = inspect(db.engine)
    names = [ix["name"] for ix in insp.get_indexes("runs")]
    names += [ck["name"] for ck in insp.get_check_constraints("runs")]
    assert names and all(n and n.startswith(("ix_runs_", "ck_runs_")) for n in names)


def _open(url: str) -> str | None:
    return current_revision(Database(url))


def test_processes_opening_a_new_file_at_once_do_not_race(tmp_path):
    url = f"sqlite:///{tmp_path / 'new.db'}"
    with mp.get_context("spawn").Pool(4) as pool:
        revisions = pool.map(_open, [url] * 8)
    assert revisions == [head_revision()] * 8


def test_sqlite_settings(db):
    with db.engine.connect() as conn:
        assert conn.exec_driver_sql("PRAGMA journal_mode").scalar() == "wal"
        assert conn.exec_driver_sql("PRAGMA foreign_keys").scalar() == 1
        assert conn.exec_driver_sql("PRAGMA busy_timeout").scalar() >= 10_000


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


def test_a_new_database_is_readable_by_its_owner_only(db):
    submit_quick(db, 2)  # a write, so that the -wal file exists
    for path in (db.path, db.path.with_name(db.path.name + "-wal")):
        assert stat.S_IMODE(path.stat().st_mode) == 0o600, path


def test_nan_and_infinity_round_trip(db):
    sub = submit_quick(db, 1)
    with db.transaction() as s:
        s.execute(update(Run).where(Run.sweep_id == sub.sweep_id).values(
            status="done", regime="complex", lambda_max=math.nan, amplitude=math.inf,
            drift=-math.inf, period=1.5, peaks=[1.0, 2.0]))
    with db.sessions() as s:
        run = s.scalars(select(Run)).one()
        assert math.isnan(run.lambda_max) and run.amplitude == math.inf
        assert run.drift == -math.inf and run.period == 1.5 and run.peaks == [1.0, 2.0]
        # In SQL, infinity is a REAL and NaN (which SQLite cannot hold) never compares true.
        raw = s.execute(text("SELECT typeof(amplitude), amplitude > 1e308, "
                             "lambda_max > 0, lambda_max <= 0 FROM runs")).one()
        assert tuple(raw) == ("real", 1, None, None)


def test_the_default_database_lives_in_the_user_data_folder(tmp_path):
    env = {"XDG_DATA_HOME": str(tmp_path / "data"), "SLOPETUI_DB": ""}
    out = slopetui_cli("db", "current", env=env)
    assert out.returncode == 0, out.stderr
    assert str(tmp_path / "data" / "slopetui" / "slopetui.db") in out.stdout


def test_works_from_a_non_editable_install(tmp_path):
    """A wheel built by `pip install .` (not -e) carries the migrations and runs them."""
    target = tmp_path / "site"
    build = subprocess.run([sys.executable, "-m", "pip", "install", "-q", "--no-deps",
                            "--target", str(target), str(ROOT)], capture_output=True,
                           text=True, timeout=600)
    assert build.returncode == 0, build.stderr
    assert (target / "migrations" / "versions").is_dir()
    assert (target / "slopetui" / "tui" / "slopetui.tcss").is_file()  # the app's styles
    env = {"PYTHONPATH": str(target)}
    code = "import slopetui, migrations; print(slopetui.__file__); print(migrations.__file__)"
    files = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                           env={**os.environ, **env}, cwd=tmp_path)
    assert all(line.startswith(str(target)) for line in files.stdout.split()), files.stdout
    url = f"sqlite:///{tmp_path / 'w.db'}"
    out = slopetui_cli("submit", "--x", "k=4:8:3", "--tau", "2", "--t-end", "100",
                       "--window", "50", "--db", url, env=env, cwd=str(tmp_path))
    assert out.returncode == 0, out.stderr
    assert "3 runs queued" in out.stdout
    cur = slopetui_cli("db", "current", "--db", url, env=env, cwd=str(tmp_path))
    assert f"revision {head_revision()} (current)" in cur.stdout


def test_reads_do_not_take_the_write_lock(db):
    """A status screen reading the store must not stall the workers' writes."""
    other = sqlite3.connect(db.path, timeout=0, isolation_level=None)
    with db.sessions() as s:
        s.execute(text("SELECT count(*) FROM runs")).scalar()
        other.execute("BEGIN IMMEDIATE")  # a writer gets in while the read is open
        other.execute("ROLLBACK")
