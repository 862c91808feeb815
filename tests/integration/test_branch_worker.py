"""A continuation computed by real `slopetui worker` pools, killed on the way: a worker
killed with SIGKILL mid-branch, then the whole pool stopped with SIGTERM between two
points; the branch resumes each time from its saved points and is finished exactly once,
with every point saved once and in order."""

from __future__ import annotations

import os
import signal

from core.branch_start import BranchSpec
from core.params import Params
from slopetui.queue import branch_jobs
from slopetui.store import branch_rows
from tests.integration.pool_support import gone, pid_of, start_pool, wait_until

#: ~0.1 s a point at tau = 10 with short steps: 80 points take several seconds, long
#: enough to be interrupted twice.
SPEC = BranchSpec(Params(tau=10.0), "k", 0.01, from_hopf=True, max_points=80, max_step=0.05)


def _row(db):
    return branch_rows.continuation(db, 1)


def test_a_branch_survives_kill_9_and_a_stop_and_finishes_once(tmp_path, db, db_url):
    cid = branch_jobs.submit(db, SPEC)
    log = tmp_path / "pool.log"
    pool = start_pool(db_url, log, "-j", "1")
    try:
        row = wait_until("5 points saved", lambda: (r := _row(db))["n_points"] >= 5 and r, 120)
        holder = row["worker_id"]
        os.kill(pid_of(holder), signal.SIGKILL)          # the worker, mid-point
        wait_until("the killed worker to be gone", lambda: gone(pid_of(holder)), 30)
        wait_until("another worker to resume it", lambda: (
            (r := _row(db))["status"] == "running" and r["worker_id"] != holder), 60)
        wait_until("more points", lambda: _row(db)["n_points"] >= row["n_points"] + 3, 60)
        pool.send_signal(signal.SIGTERM)                # a stop: between two points
        _, err = pool.communicate(timeout=60)
    finally:
        if pool.poll() is None:
            os.killpg(pool.pid, signal.SIGKILL)
            pool.communicate()
    assert pool.returncode == 0, err
    stopped = _row(db)
    assert stopped["status"] == "queued" and stopped["n_points"] < SPEC.max_points
    pool = start_pool(db_url, log, "-j", "1", "--exit-when-idle")
    _, err = pool.communicate(timeout=300)
    assert pool.returncode == 0, err
    done = _row(db)
    assert done["status"] == "done" and done["n_points"] == SPEC.max_points
    # the kill cost an attempt; the stop gave its attempt back
    assert done["attempts"] == 2
    assert [p["idx"] for p in branch_rows.points(db, cid)] == list(range(SPEC.max_points))
    text = log.read_text()
    assert text.count(f"continuation {cid} done") == 1
    assert "died (exit code -9): 1 jobs requeued" in text
    assert text.count("resumed") == 2 and "Traceback" not in text + err
