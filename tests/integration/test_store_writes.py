"""Pools on a store that refuses writes, as real processes: a read-only file is named
before the warm-up, and a write refused in the middle of the runs (a full disk, a store
turned read-only) is one line from the worker and one from the pool, no traceback, and the
pool stops (exit status 1) instead of restarting workers into the same refusal."""

from __future__ import annotations

import os
import subprocess
import time
from pathlib import Path

from slopetui.queue.pool import Pool
from slopetui.queue.worker_process import WorkerOptions, configure_logging, worker_main
from slopetui.store.open import open_store
from tests.integration.pool_support import start_pool, wait_until
from tests.integration.test_store_filesystems import tmpfs  # noqa: F401 (a fixture)
from tests.support import submit_quick


def worker_on_a_read_only_store(opts, stop, abort, pool_pid) -> None:
    """A worker whose store refuses writes from its start (the pool's probe passed)."""
    from sqlalchemy import event
    from sqlalchemy.engine import Engine

    from tests.unit.test_write_checks import _query_only
    event.listen(Engine, "connect", _query_only)
    worker_main(opts, stop, abort, pool_pid)


def test_a_refused_write_is_one_line_and_the_pool_stops(db_url, tmp_path, capfd, caplog):
    db = open_store(db_url)
    submit_quick(db, 2)
    db.dispose()
    log = tmp_path / "pool.log"
    opts = WorkerOptions(db_url=db_url, log_path=str(log), exit_when_idle=True)
    # this process's slopetui logger to the file alone, as run_pool sets it: an earlier test
    # in the same process may have left a handler on a captured stderr since closed ("---
    # Logging error ---", a traceback that is not the pool's)
    configure_logging(str(log))
    t0 = time.monotonic()
    assert Pool(opts, 2, target=worker_on_a_read_only_store).run() == 1
    # before: tracebacks, and workers restarted into the same refusal until the pool
    # gave up on its crash-loop rule (87 s); the bound leaves room for a cold warm-up
    # (20-45 s of compiling on two cores) on a loaded machine: the lines below are the test
    assert time.monotonic() - t0 < 80
    text = log.read_text()
    assert "Traceback" not in text and "Traceback" not in capfd.readouterr().err
    leaves = [line for line in text.splitlines() if " leaves: " in line]
    assert 1 <= len(leaves) <= 2 and all("attempt to write a readonly database" in line
                                         for line in leaves)
    assert caplog.text.count("the store refuses writes") == 1  # the pool's line


def _read_only_file(path: Path) -> list[str]:
    """Make the store's file read-only with its folder still writable (SQLite can create
    its -wal and -shm files): a read-only bind mount as root, whom file permissions do not
    stop; chmod otherwise. Returns the command that undoes it (as root)."""
    if os.geteuid() != 0:
        path.chmod(0o444)
        return []
    subprocess.run(["mount", "--bind", str(path), str(path)], check=True)
    subprocess.run(["mount", "-o", "remount,ro,bind", str(path)], check=True)
    return ["umount", "-l", str(path)]


def test_a_pool_on_a_read_only_file_says_so_before_its_warm_up(db_url, tmp_path):
    db = open_store(db_url)
    submit_quick(db, 2)
    db.dispose()
    undo = _read_only_file(db.path)
    try:
        log = tmp_path / "pool.log"
        t0 = time.monotonic()
        pool = start_pool(db_url, log, "-j", "2", "--exit-when-idle")
        _, err = pool.communicate(timeout=120)
        took = time.monotonic() - t0
    finally:
        if undo:
            subprocess.run(undo, check=False)
    assert pool.returncode == 1, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "attempt to write a readonly database" in lines[0], err
    assert "the pool does not start" in lines[0]
    assert "numba" not in log.read_text()  # no warm-up: before, one and worker tracebacks
    assert took < 30, took


def test_a_disk_that_fills_during_the_runs_is_one_line(tmpfs, tmp_path):  # noqa: F811
    point = tmpfs("full", "size=3m")
    url = f"sqlite:///{point / 's.db'}"
    db = open_store(url)
    submit_quick(db, 40, t_end=2e4, window=500)  # ~4 s a run: the disk fills during one
    db.dispose()
    log = tmp_path / "pool.log"  # on another file system: the log can still be written
    pool = start_pool(url, log, "-j", "2", "--exit-when-idle")
    try:
        wait_until("a worker", lambda: log.exists() and " started" in log.read_text()
                   and "worker " in log.read_text(), 120)
        with open(point / "filler", "wb") as filler:
            try:
                while True:
                    filler.write(b"\0" * 65536)
                    filler.flush()
            except OSError:
                pass
        _, err = pool.communicate(timeout=120)
    finally:
        if pool.poll() is None:
            pool.kill()
            pool.communicate()
    # before: tracebacks from every worker and the heartbeats, and a pool that hung
    assert pool.returncode == 1, err
    text = log.read_text()
    assert "Traceback" not in text and "Traceback" not in err
    assert any(" leaves: " in line and "the disk is full" in line for line in text.splitlines())
    assert "the store refuses writes" in err

