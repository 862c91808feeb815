"""A worker's memory budget (worker --memory): a batch of long windows is cut to the runs
that fit, the rest given back to the queue unstarted and computed by later batches."""

from __future__ import annotations

import re

from sqlalchemy import func, select

from core import Params, SolverSettings
from core.solve import make_grid, memory_of
from slopetui.queue.batch_memory import MIB, OVERHEAD, fitting, run_bytes
from slopetui.queue.jobs import Job, claim_batch
from slopetui.queue.pool import Pool
from slopetui.queue.worker_process import BATCHED_METHODS, WorkerOptions, _within_memory
from slopetui.store import Run
from slopetui.sweeps.spec import parse_spec
from slopetui.sweeps.submit import submit

#: Euler to t = 400 with a window of 200: 2e4 window samples, ~2 MB a run.
SOLVER = {"method": "euler", "dt": 1e-3, "t_end": 400.0, "window": 200.0}


def job(tau: float = 10.0, window: float = 200.0) -> Job:
    settings = SolverSettings(**{**SOLVER, "window": window})
    return Job(1, 1, 0, "x", Params(tau=tau), settings)


def test_a_run_counts_what_the_engine_lays_out():
    j = job()
    assert run_bytes(j) == memory_of(make_grid(j.params, j.settings), j.settings).total
    assert run_bytes(job(tau=100.0)) > run_bytes(j)  # the delay ring grows with tau
    assert run_bytes(job(tau=1e9)) == 0  # a ring over 2 GiB, refused by the engine: it fails on its own


def test_the_leading_runs_that_fit_are_kept_and_at_least_one():
    batch = [job() for _ in range(10)]
    each = OVERHEAD * run_bytes(batch[0])
    assert fitting(batch, int(3.5 * each)) == 3
    assert fitting(batch, int(100 * each)) == 10
    assert fitting(batch, 1) == 1  # alone over the budget: core.solve refuses what is too big
    assert fitting([], 1) == 0


def test_a_worker_cuts_its_batches_to_the_budget_and_computes_every_run(db, db_url, capfd):
    spec = parse_spec({"x": {"param": "k", "start": 4, "stop": 12, "num": 12},
                       "solver": {**SOLVER, "window": 1000.0, "t_end": 2000.0}})
    submit(db, spec)
    with db.sessions() as s:
        first = s.scalars(select(Run).limit(1)).one()
        settings = SolverSettings(method="euler", dt=1e-3, t_end=2000.0, window=1000.0)
        per_run = OVERHEAD * memory_of(make_grid(Params(k=first.k, tau=first.tau), settings),
                                       settings).total
    budget_mib = 64
    fits = int(budget_mib * MIB // per_run)
    assert 1 < fits < 12  # the test means something: a cut, and batches of several
    opts = WorkerOptions(db_url=db_url, exit_when_idle=True, batch=12, memory_mib=budget_mib)
    assert Pool(opts, 1).run() == 0
    with db.sessions() as s:
        assert s.scalar(select(func.count()).where(Run.status == "done")) == 12
        assert s.scalar(select(func.max(Run.attempts))) == 1  # given back unstarted: uncharged
    captured = capfd.readouterr()  # the worker process logs to the pool's stdout or stderr
    log = captured.out + captured.err
    sizes = [int(n) for n in re.findall(r"batch of (\d+)\)", log)]
    assert sizes and max(sizes) == fits
    assert f"batch cut to {fits} of 12 runs" in log


def test_a_run_counts_its_lanes_of_the_batched_kernels_rings():
    """The batched kernels hold every lane's delay ring at once: N x lanes x 8 bytes per
    buffered variable (m_x for Euler, m_x and m_y for RK4), as much again for the tangent
    with lambda_max. Each run counts its lane of them (and its samples and logs), so a
    batch's sum over its runs covers the rings."""
    for method, dt, variables in (("euler", 1e-3, 1), ("rk4", 1e-2, 2)):
        settings = SolverSettings(method=method, dt=dt, t_end=400.0, window=200.0)
        g = make_grid(Params(tau=10.0), settings)
        assert memory_of(g, settings).ring >= g.n_delay * variables * 8 * 2, method


def claimed(db, method: str, n: int, batched) -> list[Job]:
    """n runs of ``method`` submitted and claimed in one batch, with a ~5 MB window each."""
    submit(db, parse_spec({"x": {"param": "k", "start": 4, "stop": 12, "num": n},
                           "solver": {"method": method, "dt": 0.01, "t_end": 2000.0,
                                      "window": 1000.0}}))
    batch = claim_batch(db, "w", n, batched)
    assert len(batch) == n
    return batch


def test_an_rk4_batch_is_cut_to_the_budget_like_an_euler_batch(db):
    """RK4 batches go through the batched kernels (BATCHED_METHODS), every lane's buffers
    held at once: they are cut, and the runs cut off go back to the queue unstarted."""
    assert "rk4" in BATCHED_METHODS
    batch = claimed(db, "rk4", 4, BATCHED_METHODS)
    assert fitting(batch, MIB) == 1  # ~5 MB a run
    kept = _within_memory(db, "w", batch, memory_mib=1)
    assert [job.run_id for job in kept] == [batch[0].run_id]
    with db.sessions() as s:
        assert sorted(s.scalars(select(Run.status))) == ["queued"] * 3 + ["running"]
        assert s.scalar(select(func.max(Run.attempts))) == 0


def test_a_batch_computed_run_by_run_is_not_cut(db):
    """A method without a batched kernel (stiff) is computed one run at a time (a worker
    claims it alone; claimed together, as claim_batch does for batched=None, it is still
    computed run by run): one run's buffers are held at once, so the budget leaves the
    batch whole."""
    assert "stiff" not in BATCHED_METHODS
    batch = claimed(db, "stiff", 3, None)
    assert _within_memory(db, "w", batch, memory_mib=1) == batch
