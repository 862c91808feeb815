"""A continuation computed by real `slopetui worker` pools, killed on the way: a worker
killed with SIGKILL mid-branch, then the whole pool stopped with SIGTERM between two
points; the branch resumes each time from its saved points and is finished exactly once,
with every point saved once and in order."""

from __future__ import annotations

from core.branch_start import BranchSpec
from core.params import Params
from slopetui.queue import branch_jobs
from slopetui.store.jobs import continuations
from tests.integration.pool_support import interrupt_twice_then_finish

#: ~0.1 s a point at tau = 10 with short steps; the two interruptions take about ten points
#: (measured: the worker killed after 5 points were saved, the pool stopped after 8; 80
#: points then took 7 s more to finish): 30 points leave twenty to spare.
SPEC = BranchSpec(Params(tau=10.0), "k", 0.01, from_hopf=True, max_points=30, max_step=0.05)


def _row(db):
    return continuations.continuation(db, 1)


def test_a_branch_survives_kill_9_and_a_stop_and_finishes_once(tmp_path, db, db_url):
    cid = branch_jobs.submit(db, SPEC)
    log = tmp_path / "pool.log"
    err = interrupt_twice_then_finish(db_url, log, lambda: _row(db), "n_points", SPEC.max_points)
    done = _row(db)
    assert done.status == "done" and done.n_points == SPEC.max_points
    # the kill cost an attempt; the stop gave its attempt back
    assert done.attempts == 2
    assert [p.idx for p in continuations.points(db, cid)] == list(range(SPEC.max_points))
    text = log.read_text()
    assert text.count(f"continuation {cid} done") == 1
    assert "died (exit code -9): 1 jobs requeued" in text
    assert text.count("resumed") == 2 and "Traceback" not in text + err
