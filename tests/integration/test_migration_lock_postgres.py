"""Migrations of one PostgreSQL database from several hosts at once:
the lock is the server's advisory lock, not a file on each host. Each process here gets
a cache folder of its own, as on hosts that share no file system: with the old file
lock, four simultaneous `slopetui db upgrade` on an empty database failed two times in
four (a duplicate key on pg_type_typname_nsp_index)."""

from __future__ import annotations

import os
import subprocess
import sys

from sqlalchemy import text

from slopetui.store.database import Database
from slopetui.store.migrate import current_revision, head_revision, migration_lock
from tests.integration.pool_support import wait_until


def _upgrade(url: str, cache: str) -> subprocess.Popen[str]:
    """`slopetui db upgrade` in a process whose per-host folders are its own."""
    env = {**os.environ, "XDG_CACHE_HOME": cache, "XDG_STATE_HOME": cache}
    return subprocess.Popen([sys.executable, "-m", "slopetui", "db", "upgrade", "--db", url],
                            env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)


def test_four_hosts_upgrading_at_once_all_succeed(tmp_path, pg_server):
    for attempt in range(3):  # a race shows itself often, not always: three tries
        with pg_server.database(migrated=False) as url:
            procs = [_upgrade(url, str(tmp_path / f"host{attempt}{i}")) for i in range(4)]
            outs = [p.communicate(timeout=120) for p in procs]
            codes = [p.returncode for p in procs]
            assert codes == [0, 0, 0, 0], [err for _, err in outs]
            said = sorted(out.strip().rsplit(": ", 1)[1] for out, _ in outs)
            # exactly one migrated, the others found it done
            assert said == [f"already at {head_revision()}"] * 3 + [f"empty -> {head_revision()}"]
            db = Database(url)
            assert current_revision(db) == head_revision()
            db.dispose()


def _waiting_for_a_lock(db: Database) -> bool:
    """Someone waits for an advisory lock on ``db``'s database (pg_locks: not granted)."""
    with db.engine.connect() as conn:
        return bool(conn.execute(text(
            "SELECT count(*) FROM pg_locks WHERE locktype = 'advisory' AND NOT granted "
            "AND database = (SELECT oid FROM pg_database WHERE datname = current_database())"
        )).scalar_one())


def test_an_upgrade_waits_for_the_lock_held_elsewhere(tmp_path, pg_server):
    with pg_server.database(migrated=False) as url:
        holder = Database(url)
        with migration_lock(holder):
            proc = _upgrade(url, str(tmp_path / "other"))
            # seen waiting in the server's lock table, where a fixed sleep of 4 s only
            # gave it time to migrate (a start takes ~1 s)
            wait_until("the upgrade to wait for the lock",
                       lambda: proc.poll() is not None or _waiting_for_a_lock(holder), 60)
            assert proc.poll() is None, proc.communicate()
            assert current_revision(holder) is None  # nothing created while it waits
        _, err = proc.communicate(timeout=60)
        assert proc.returncode == 0, err
        assert current_revision(holder) == head_revision()
        holder.dispose()
