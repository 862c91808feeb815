"""A new SQLite store's first connection switches the file to WAL: the pragma reads the
file, then takes its write lock. When another connection held that lock (processes opening
one new store at once), SQLite answered "database is locked" at once, busy_timeout or not.
The switch waits for the writer instead."""

from __future__ import annotations

import sqlite3
import threading

from slopetui.store.database import Database


def test_the_switch_to_wal_waits_for_a_writer(tmp_path):
    path = tmp_path / "new.db"
    other = sqlite3.connect(path, isolation_level=None, check_same_thread=False)
    other.execute("CREATE TABLE t (x)")  # a rollback-journal file, as a new one is
    other.execute("BEGIN IMMEDIATE")  # its write lock, held
    release = threading.Timer(0.3, lambda: other.execute("COMMIT"))
    release.start()
    try:
        db = Database(f"sqlite:///{path}")
        with db.read() as conn:
            assert conn.exec_driver_sql("PRAGMA journal_mode").scalar() == "wal"
        db.dispose()
    finally:
        release.join()
        other.close()
