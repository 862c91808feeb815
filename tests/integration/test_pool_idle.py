"""Pools that leave on their own, as real processes: --exit-when-idle waits out a paused
sweep (for the grace period) instead of leaving with its runs queued, and the
application's pool (--owner-pid) leaves once its owner has quit and the store is idle
(the decisions themselves: tests/unit/test_idle_exit.py)."""

from __future__ import annotations

import subprocess
import time

from slopetui.queue.local_pool import store_key
from slopetui.queue.open_apps import record_app
from slopetui.store.open import open_store
from slopetui.sweeps import control
from tests.integration.pool_support import by_status, start_pool, wait_until
from tests.support import submit_quick


def _worker_started(log) -> bool:
    return log.exists() and "started" in log.read_text() and " worker " in log.read_text()


def _finish(pool: subprocess.Popen[str], timeout: float) -> str:
    try:
        _, err = pool.communicate(timeout=timeout)
    finally:
        if pool.poll() is None:
            pool.kill()
            pool.communicate()
    return err


def test_a_paused_sweep_keeps_an_exit_when_idle_pool_until_it_is_resumed(db_url, tmp_path):
    db = open_store(db_url)
    sub = submit_quick(db, 3)
    control.pause(db, sub.sweep_id)
    log = tmp_path / "pool.log"
    pool = start_pool(db_url, log, "-j", "1", "--exit-when-idle")  # the default grace, 60 s
    try:
        wait_until("the worker", lambda: _worker_started(log), 120)
        time.sleep(3.0)
        # the old rule read "nothing queued" and the pool was gone here, 3 runs queued
        assert pool.poll() is None, log.read_text()
        control.resume(db, sub.sweep_id)
        err = _finish(pool, 120)
    finally:
        if pool.poll() is None:
            pool.kill()
    assert pool.returncode == 0, err
    assert by_status(db) == {"done": 3}
    assert "leaving: nothing queued or running" in log.read_text()


def test_a_paused_sweep_is_left_after_the_grace_period_saying_why(db_url, tmp_path):
    db = open_store(db_url)
    sub = submit_quick(db, 3)
    control.pause(db, sub.sweep_id)
    log = tmp_path / "pool.log"
    pool = start_pool(db_url, log, "-j", "1", "--exit-when-idle", "--idle-grace", "1")
    err = _finish(pool, 120)
    assert pool.returncode == 0, err
    assert ("leaving: nothing claimable for 1 s (3 runs queued in paused sweeps)"
            in log.read_text())
    assert by_status(db) == {"queued": 3}


def test_the_applications_pool_leaves_once_its_owner_has_quit_and_the_store_is_idle(
        db_url, tmp_path):
    db = open_store(db_url)
    submit_quick(db, 2)
    owner = subprocess.Popen(["sleep", "600"])  # stands for the application
    log = tmp_path / "pool.log"
    pool = start_pool(db_url, log, "-j", "1", "--owner-pid", str(owner.pid),
                      "--idle-grace", "1")
    try:
        wait_until("the runs", lambda: by_status(db) == {"done": 2}, 120)
        time.sleep(3.0)  # idle for longer than the grace: the owner still runs
        assert pool.poll() is None, log.read_text()
        owner.kill()
        owner.wait()
        t0 = time.monotonic()
        err = _finish(pool, 60)
        took = time.monotonic() - t0
    finally:
        if owner.poll() is None:
            owner.kill()
        if pool.poll() is None:
            pool.kill()
    assert pool.returncode == 0, err
    assert took < 15, took
    assert (f"the process that started the pool (pid {owner.pid}) and the applications of "
            "the store have quit, and nothing was claimable or running for 1 s"
            ) in log.read_text()


def test_a_second_application_keeps_the_pool_the_first_one_started(db_url, tmp_path,
                                                                    monkeypatch):
    db = open_store(db_url)
    log = tmp_path / "pool.log"
    monkeypatch.setenv("XDG_STATE_HOME", str(log.parent / "state"))  # the pool's (pool_env)
    first = subprocess.Popen(["sleep", "600"])   # the application that starts the pool
    second = subprocess.Popen(["sleep", "600"])  # one that found it
    record_app(store_key(db.url.render_as_string(hide_password=False)), second.pid)
    pool = start_pool(db_url, log, "-j", "1", "--owner-pid", str(first.pid),
                      "--idle-grace", "1")
    try:
        wait_until("the worker", lambda: _worker_started(log), 120)
        first.kill()
        first.wait()
        time.sleep(4.0)  # idle, its owner gone: the second application keeps it
        assert pool.poll() is None, log.read_text()
        second.kill()
        second.wait()
        err = _finish(pool, 60)
    finally:
        for proc in (first, second, pool):
            if proc.poll() is None:
                proc.kill()
    assert pool.returncode == 0, err
