"""The reproduction of a poisoned queue, with a real `slopetui worker`: a run with
dt = 0 set by hand, and beside it a continuation and a hysteresis sweep with a parameter
out of range. Until then the worker died in claim_batch at each claim (ParameterError in
core.params, before the run was charged an attempt), the pool gave up after six
tracebacks with exit status 1, and the other runs stayed queued, for every later pool
too. Now each poisoned row fails at its claim with its reason, in one log line, and the
pool computes the rest and leaves with status 0. On SQLite and PostgreSQL."""

from __future__ import annotations

import re
import subprocess
import sys

from sqlalchemy import select, update

from core.branch_start import BranchSpec
from core.params import Params
from slopetui.queue import branch_jobs, hysteresis_jobs
from slopetui.queue.hysteresis_jobs import HysteresisSpec
from slopetui.store.jobs import continuations, hysteresis_sweeps
from slopetui.store.models import Continuation, HysteresisSweep, Run
from tests.integration.pool_support import pool_env
from tests.support import slopetui_cli


def test_a_pool_fails_the_poisoned_rows_computes_the_rest_and_exits_0(store, store_url,
                                                                       tmp_path):
    out = slopetui_cli("submit", "--x", "k=4:12:4", "--tau", "2.3", "--t-end", "2000",
                       "--window", "500", "--db", store_url)
    assert out.returncode == 0, out.stderr
    branch = branch_jobs.submit(store, BranchSpec(Params(tau=2.0), "k", 0.01, from_hopf=True,
                                                  max_points=7))
    sweep = hysteresis_jobs.submit(store, HysteresisSpec(Params(tau=2.0), "k", 8.0, 12.0, 4,
                                                         0.01, 300.0, 100.0))
    with store.transaction() as s:  # by hand, as with the sqlite3 shell or psql
        s.execute(update(Run).where(Run.id == 2).values(dt=0.0))
        s.execute(update(Continuation).where(Continuation.id == branch).values(k=-1.0))
        s.execute(update(HysteresisSweep).where(HysteresisSweep.id == sweep).values(dt=0.0))
    log = tmp_path / "pool.log"
    pool = subprocess.run(
        [sys.executable, "-m", "slopetui", "worker", "-j", "1", "--exit-when-idle",
         "--max-attempts", "2", "--db", store_url, "--log", str(log)],
        capture_output=True, text=True, timeout=300, env=pool_env(log))
    text = log.read_text()
    assert pool.returncode == 0, text + pool.stderr
    assert "Traceback" not in text + pool.stderr and "died" not in text
    with store.sessions() as s:
        runs = {run.id: run for run in s.scalars(select(Run))}
    assert {i: run.status for i, run in runs.items()} == {1: "done", 2: "failed", 3: "done",
                                                          4: "done"}
    # SQLite's RETURNING gives a whole REAL as an integer: "0" or "0.0"
    assert re.fullmatch(r"not computed: invalid input in the store: dt = 0(\.0)? is out of "
                        r"range: allowed dt > 0", runs[2].error), runs[2].error
    assert runs[2].attempts == 0
    assert text.count("run 2 failed at its claim: ") == 1
    continuation = continuations.continuation(store, branch)
    assert continuation is not None and continuation.status == "failed"
    assert "k = -1.0 is out of range: allowed k >= 0" in continuation.error
    assert text.count(f"continuation {branch} failed at its claim: ") == 1
    hysteresis = hysteresis_sweeps.hysteresis_sweep(store, sweep)
    assert hysteresis is not None and hysteresis.status == "failed"
    assert "allowed dt > 0" in hysteresis.error
    assert text.count(f"hysteresis sweep {sweep} failed at its claim: ") == 1
