"""The store from other processes: `slopetui db upgrade` and the default location in a fresh
process, processes opening a new store at once, and a plain (non-editable) install (the
store in one process: tests/unit/test_store.py).

The first migration runs on SQLite and PostgreSQL (``new_store_url``); the default location
is a SQLite file (``sqlite_only``), and the plain install's store is incidental (SQLite)."""

from __future__ import annotations

import multiprocessing as mp
import os
import subprocess
import sys
from pathlib import Path

import pytest
from sqlalchemy import inspect

from slopetui.store.database import Database
from slopetui.store.migrate import current_revision, head_revision
from slopetui.store.open import open_store
from tests.support import slopetui_cli

ROOT = Path(__file__).resolve().parents[2]


def test_an_empty_database_upgrades_to_head(new_store_url):
    db = Database(new_store_url)
    assert current_revision(db) is None
    assert slopetui_cli("db", "upgrade", "--db", new_store_url).returncode == 0
    assert current_revision(db) == head_revision()
    assert {"sweeps", "runs", "workers", "alembic_version"} <= set(inspect(db.engine).get_table_names())
    again = slopetui_cli("db", "upgrade", "--db", new_store_url)
    assert "already at" in again.stdout
    db.dispose()


def _open(url: str) -> str | None:
    db = open_store(url)
    try:
        return current_revision(db)
    finally:
        db.dispose()  # no connection left behind for the database's drop


def test_processes_opening_a_new_store_at_once_do_not_race(new_store_url):
    """One of them migrates, under the migration lock (a file lock beside a SQLite file,
    an advisory lock on PostgreSQL); the others wait for it and find the schema made."""
    with mp.get_context("spawn").Pool(4) as pool:
        revisions = pool.map(_open, [new_store_url] * 8)
    assert revisions == [head_revision()] * 8


@pytest.mark.sqlite_only
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
