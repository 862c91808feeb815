"""A store that refuses writes (slopetui.store.write_checks): the probe a pool runs before
its warm-up, on SQLite and PostgreSQL (``store``), the one line for a refused write, and a
pool that fails without leaving its workers behind (workers on real read-only and full
file systems: tests/integration/test_store_writes.py)."""

from __future__ import annotations

import sqlite3
import time
from collections.abc import Iterator
from contextlib import contextmanager

import pytest
from sqlalchemy import event, text
from sqlalchemy.engine import Engine
from sqlalchemy.exc import OperationalError

from slopetui.queue import pool as pool_module
from slopetui.queue.worker_process import WorkerOptions
from slopetui.store import write_checks
from slopetui.store.database import Database
from slopetui.store.open import open_store
from slopetui.store.write_checks import refuses_writes, write_refusal


def _query_only(dbapi_connection, _record) -> None:
    dbapi_connection.execute("PRAGMA query_only = ON")


@contextmanager
def read_only_sqlite() -> Iterator[None]:
    """Every SQLite connection this process opens refuses writes, as a read-only file
    does ("attempt to write a readonly database"), without root or a mount."""
    event.listen(Engine, "connect", _query_only)
    try:
        yield
    finally:
        event.remove(Engine, "connect", _query_only)


@contextmanager
def read_only(store: Database) -> Iterator[Database]:
    """The store, opened again so that it refuses writes."""
    if store.is_sqlite:
        with read_only_sqlite():
            yield Database(store.url.render_as_string(hide_password=False))
        return
    with store.connection() as conn:  # the test's own database (store fixture)
        name = conn.exec_driver_sql("SELECT current_database()").scalar()
        conn.exec_driver_sql(f'ALTER DATABASE "{name}" SET default_transaction_read_only = on')
    again = Database(store.url.render_as_string(hide_password=False))
    try:
        yield again
    finally:
        again.dispose()
        with store.connection() as conn:
            conn.exec_driver_sql(f'ALTER DATABASE "{name}" RESET default_transaction_read_only')


def test_a_writable_store_passes_the_probe(store):
    assert refuses_writes(store) is None


def test_a_read_only_store_is_refused_in_one_line(store):
    with read_only(store) as ro:
        line = refuses_writes(ro)
    assert line is not None and len(line.splitlines()) == 1
    assert ("readonly" in line) if store.is_sqlite else ("read-only transaction" in line)


def test_a_full_disk_beside_a_sqlite_file_is_refused(db, monkeypatch):
    monkeypatch.setattr(write_checks, "free_bytes", lambda _path: 4096)
    assert refuses_writes(db) == (f"cannot write {db.path}: the disk is full (4 kB free in "
                                  f"{db.path.parent})")


def _error(message: str) -> OperationalError:
    return OperationalError("UPDATE runs SET ...", {}, sqlite3.OperationalError(message))


def test_only_refused_writes_get_the_one_line(db):
    assert write_refusal(db, _error("database or disk is full")) == (
        f"cannot write {db.path}: the disk is full (database or disk is full)")
    assert "attempt to write a readonly database" in write_refusal(
        db, _error("attempt to write a readonly database"))
    assert write_refusal(db, _error("database is locked")) is None  # retried, not refused
    assert write_refusal(db, ValueError("readonly")) is None


def test_a_pool_on_a_read_only_store_stops_before_its_warm_up(db_url, monkeypatch, caplog):
    open_store(db_url).dispose()
    monkeypatch.setattr(pool_module, "pool_warm_up",
                        lambda _stopped: pytest.fail("warmed up for a store it cannot write"))
    with read_only_sqlite():
        assert pool_module.Pool(WorkerOptions(db_url=db_url, exit_when_idle=True), 1).run() == 1
    errors = [r.getMessage() for r in caplog.records if r.levelname == "ERROR"]
    assert len(errors) == 1 and "readonly" in errors[0] and "the pool does not start" in errors[0]


def waiting_worker(_opts, stop, abort, _pool_pid) -> None:
    """A worker that leaves only on an abort (or after 30 s)."""
    deadline = time.monotonic() + 30
    while not abort.is_set() and time.monotonic() < deadline:
        time.sleep(0.05)


def test_a_pool_that_fails_takes_its_workers_with_it(db_url, monkeypatch):
    open_store(db_url).dispose()
    monkeypatch.setattr(pool_module, "pool_warm_up", lambda _stopped: 0.0)
    ticks = []

    def failing_tick(_self, force: bool = False) -> None:
        ticks.append(1)
        if len(ticks) > 1:
            raise RuntimeError("the pool's own statement failed")
    monkeypatch.setattr(pool_module.Progress, "tick", failing_tick)
    pool = pool_module.Pool(WorkerOptions(db_url=db_url), 2, target=waiting_worker)
    with pytest.raises(RuntimeError):
        pool.run()
    # before: the workers outlived the failed pool, and its exit waited for them
    assert not any(proc.is_alive() for proc in pool.procs.values())


def test_the_probe_commits_nothing(db):
    with db.sessions() as s:
        before = s.execute(text("SELECT count(*) FROM runs")).scalar()
    assert refuses_writes(db) is None
    with db.sessions() as s:
        assert s.execute(text("SELECT count(*) FROM runs")).scalar() == before
