"""A continuation computed by real `slopetui worker` pools, killed on the way: a worker
killed with SIGKILL mid-branch, then the whole pool stopped with SIGTERM between two
points; the branch resumes each time from its saved points and is finished exactly once,
with every point saved once and in order. From the first Hopf point and from the second
(the index is stored with the row: a worker that resumes it starts from the same one)."""

from __future__ import annotations

import json
from dataclasses import replace

import numpy as np
import pytest

from core.branch_start import BranchSpec
from core.params import Params
from core.stability import hopf_k
from slopetui.cli import main
from slopetui.queue import branch_jobs
from slopetui.store.jobs import continuations
from tests.integration.pool_support import interrupt_twice_then_finish, start_pool

#: ~0.1 s a point at tau = 10 with short steps; the two interruptions take about ten points
#: (measured: the worker killed after 5 points were saved, the pool stopped after 8; 80
#: points then took 7 s more to finish): 30 points leave twenty to spare.
SPEC = BranchSpec(Params(tau=10.0), "k", 0.01, from_hopf=True, max_points=30, max_step=0.05)


def _row(db):
    return continuations.continuation(db, 1)


@pytest.mark.parametrize("hopf_branch", [1, 2])
def test_a_branch_survives_kill_9_and_a_stop_and_finishes_once(tmp_path, db, db_url,
                                                                 hopf_branch):
    cid = branch_jobs.submit(db, replace(SPEC, hopf_branch=hopf_branch))
    log = tmp_path / "pool.log"
    err = interrupt_twice_then_finish(db_url, log, lambda: _row(db), "n_points", SPEC.max_points)
    done = _row(db)
    assert done.status == "done" and done.n_points == SPEC.max_points
    # resumed twice from the Hopf point it was queued at: the 2nd lies at k = 6.678
    assert done.hopf_branch == hopf_branch
    assert abs(done.hopf_value / hopf_k(10.0, Params().F1, hopf_branch) - 1) < 5e-4
    # the kill cost an attempt; the stop gave its attempt back
    assert done.attempts == 2
    assert [p.idx for p in continuations.points(db, cid)] == list(range(SPEC.max_points))
    text = log.read_text()
    assert text.count(f"continuation {cid} done") == 1
    assert "died (exit code -9): 1 jobs requeued" in text
    assert text.count("resumed") == 2 and "Traceback" not in text + err
    assert text.count(f"from Hopf point {hopf_branch}: resumed") == 2


def test_a_queued_branch_from_the_second_hopf_point_is_the_one_computed_here(
        tmp_path, db, db_url, capsys):
    """`continue --from-hopf 2 --submit` used to exit 2 (no place for the index); queued,
    a worker computes the same branch as `continue --from-hopf 2` without --submit."""
    asked = ["continue", "--param", "k", "--from-hopf", "2", "--tau", "10", "--points", "8",
             "--max-step", "0.05"]
    assert main([*asked, "--json"]) == 0
    here = json.loads(capsys.readouterr().out)
    assert main([*asked, "--submit", "--db", db_url]) == 0
    pool = start_pool(db_url, tmp_path / "pool.log", "-j", "1", "--exit-when-idle")
    _, err = pool.communicate(timeout=300)
    assert pool.returncode == 0, err
    capsys.readouterr()
    assert main(["branch", "1", "--db", db_url, "--json"]) == 0
    stored = json.loads(capsys.readouterr().out)
    assert stored["status"] == "done" and stored["hopf_branch"] == 2
    assert stored["hopf_value"] == pytest.approx(here["hopf"]["value"], rel=1e-12)
    assert stored["hopf_period"] == pytest.approx(here["hopf"]["period"], rel=1e-12)
    columns = ("value", "period", "amplitude")
    got, want = ([[p[c] for c in columns] for p in branch] for branch in
                 (stored["branch"], here["branch"]))
    assert len(got) == len(want) == 8
    np.testing.assert_allclose(got, want, rtol=1e-9)
    assert [p["stable"] for p in stored["branch"]] == [p["stable"] for p in here["branch"]]
