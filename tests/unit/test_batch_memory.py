"""A worker's memory budget (worker --memory): a batch of long windows is cut to the runs
that fit, the rest given back to the queue unstarted and computed by later batches."""

from __future__ import annotations

import re

from sqlalchemy import func, select

from core import Params, SolverSettings
from core.solve import make_grid, memory_of
from slopetui.queue.batch_memory import MIB, OVERHEAD, fitting, run_bytes
from slopetui.queue.jobs import Job
from slopetui.queue.pool import Pool
from slopetui.queue.worker_process import WorkerOptions
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


def test_a_batch_computed_run_by_run_is_not_cut(db, db_url, capfd):
    """RK4 batches are computed one run at a time (worker_process.BATCHED_METHODS): only
    one run's buffers are held at once, so the budget leaves them whole."""
    spec = parse_spec({"x": {"param": "k", "start": 4, "stop": 12, "num": 4},
                       "solver": {"method": "rk4", "dt": 0.01, "t_end": 2000.0, "window": 1000.0}})
    submit(db, spec)
    opts = WorkerOptions(db_url=db_url, exit_when_idle=True, batch=4, memory_mib=1)
    assert Pool(opts, 1).run() == 0
    captured = capfd.readouterr()
    assert "batch cut" not in captured.out + captured.err
    with db.sessions() as s:
        assert s.scalar(select(func.count()).where(Run.status == "done")) == 4
