"""A pool killed with kill -9 leaves no worker behind: its workers notice from their first
second (PR_SET_PDEATHSIG, and the pool's pid checked against getppid()), during their
warm-up as well as idle or busy, and leave the store as they should.

Idle and busy run on SQLite and PostgreSQL (``store``): a busy orphan finishes its run and
gives the rest back. The warm-up case runs on SQLite only, for time: its workers never
reach the store."""

from __future__ import annotations

import contextlib
import os
import signal
from pathlib import Path

from sqlalchemy import select

from slopetui.store.models import Run
from tests.integration.pool_support import (
    MEDIUM,
    by_status,
    done_lines,
    gone,
    live_worker_rows,
    start_pool,
    started_run,
    wait_until,
)
from tests.support import submit_quick

#: Workers whose pool died must be gone within this many seconds (a busy one first
#: finishes the ~0.2 s run in its kernel).
ORPHAN_BOUND_S = 15.0


def worker_children(pool_pid: int) -> list[int]:
    """The pool's worker processes (not multiprocessing's resource tracker)."""
    found = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
            command = (stat.parent / "cmdline").read_bytes()
        except (OSError, IndexError):
            continue
        if int(fields[1]) == pool_pid and b"spawn_main" in command:
            found.append(int(stat.parent.name))
    return found


def kill_group(pool) -> None:
    """Clean up whatever a failed test left (the pool is its process group's leader)."""
    with contextlib.suppress(ProcessLookupError):
        os.killpg(pool.pid, signal.SIGKILL)
    pool.communicate()


def test_workers_exit_when_the_pool_is_killed_during_their_warm_up(tmp_path, db, db_url):
    submit_quick(db, 4)
    pool = start_pool(db_url, tmp_path / "pool.log", "-j", "2", group=True)
    try:
        kids = wait_until("two workers spawned",
                          lambda: len(k := worker_children(pool.pid)) == 2 and k)
        os.kill(pool.pid, signal.SIGKILL)  # the workers are still importing / warming up
        pool.wait()
        wait_until("the orphans to exit", lambda: all(gone(k) for k in kids), ORPHAN_BOUND_S)
    finally:
        kill_group(pool)
    assert live_worker_rows(db) == []   # none registered, or stopped
    assert by_status(db) == {"queued": 4}  # none claimed a run


def test_idle_and_busy_workers_exit_when_the_pool_is_killed(tmp_path, store, store_url):
    log = tmp_path / "pool.log"
    pool = start_pool(store_url, log, "-j", "2", "--batch", "3", group=True)
    try:
        wait_until("two workers", lambda: len(live_worker_rows(store)) == 2)
        kids = worker_children(pool.pid)
        submit_quick(store, 3, **MEDIUM)  # one worker takes the batch, the other stays idle
        in_kernel = wait_until("a run in a kernel", lambda: started_run(store)).id
        os.kill(pool.pid, signal.SIGKILL)
        pool.wait()
        wait_until("the orphans to exit", lambda: all(gone(k) for k in kids), ORPHAN_BOUND_S)
    finally:
        kill_group(pool)
    assert live_worker_rows(store) == []  # both rows say stopped
    counts = by_status(store)
    assert "running" not in counts and sum(counts.values()) == 3
    with store.sessions() as s:
        runs = {r.id: r for r in s.scalars(select(Run))}
    assert runs[in_kernel].status == "done"  # the busy one finished its run first
    lines = done_lines(log)
    for run in runs.values():
        assert (lines[run.id], run.attempts) == ((1, 1) if run.status == "done" else (0, 0))
    assert "is gone" in log.read_text()
