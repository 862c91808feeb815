"""A worker's memory budget (worker --memory): a batch of long windows is cut to the runs
that fit, the rest given back to the queue unstarted and computed by later batches."""

from __future__ import annotations

import re
import tracemalloc

import numpy as np
from sqlalchemy import func, select

from core.batch import MIN_LANES, VECTOR
from core.closure import closure_flags, uphill_flags
from core.params import Params
from core.point import SAMPLE_BLOCK, _negative_variance, _sample_flags, run_batch, run_point
from core.solve import SolverSettings, _sample_times, make_grid, memory_of, moved_into, simulate, trajectory_of
from slopetui.queue.batch_memory import MIB, OVERHEAD, REDO, charge, fitting, fitting_sizes, run_bytes
from slopetui.queue.jobs import Job, claim_batch
from slopetui.queue.pool import Pool
from slopetui.queue.run_batches import BATCHED_METHODS, _within_memory
from slopetui.queue.worker_process import WorkerOptions
from slopetui.store.models import Run
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
    size = run_bytes(batch[0])
    assert MIN_LANES - 1 == 3 and VECTOR == 8  # 3 runs are the single kernel's, 4-8 one vector
    assert charge([size] * 3) == OVERHEAD * 3 * size + REDO * size
    assert fitting(batch, int(charge([size] * 3)) + 1) == 3
    # a 4th run pads the call to 8 lanes, each holding a run's buffers: no more fit until 8
    assert charge([size] * 4) == charge([size] * 8) == OVERHEAD * 8 * size + REDO * size
    assert fitting(batch, int(charge([size] * 8)) - 1) == 3
    assert fitting(batch, int(charge([size] * 8)) + 1) == 8
    assert fitting(batch, int(100 * size)) == 10
    assert fitting(batch, 1) == 1  # alone over the budget: core.solve refuses what is too big
    assert fitting([], 1) == 0
    # the analysis's one run more is the largest run's
    assert charge([size, 5 * size]) == OVERHEAD * 6 * size + REDO * 5 * size


def test_a_worker_cuts_its_batches_to_the_budget_and_computes_every_run(db, db_url, capfd):
    spec = parse_spec({"x": {"param": "k", "start": 4, "stop": 12, "num": 12},
                       "solver": {**SOLVER, "window": 1000.0, "t_end": 2000.0}})
    submit(db, spec)
    with db.sessions() as s:
        first = s.scalars(select(Run).limit(1)).one()
        settings = SolverSettings(method="euler", dt=1e-3, t_end=2000.0, window=1000.0)
        per_run = memory_of(make_grid(Params(k=first.k, tau=first.tau), settings), settings).total
    budget_mib = 64
    fits = fitting_sizes([per_run] * 12, budget_mib * MIB)
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


# -- what a batch holds: core.point.run_batch, core.solve.moved_into --------------------

#: Lanes that the stiff scheme integrates again (Euler drives s_y below 0: core.point) to
#: the end, at t_end = 2000: k = 6.25, 6.5, 6.75 and 7 do, 7.25 does not (measured).
REDONE = [Params(k=k, b=9.0, tau=0.2) for k in (6.25, 6.5, 6.75, 7.0, 7.25)]
REDO_SETTINGS = SolverSettings(method="euler", dt=1e-3, t_end=2000.0, window=1000.0, lyap=True)


def test_a_batch_writes_its_re_integrations_over_the_lanes_samples():
    """A lane re-integrated by the stiff scheme keeps no arrays of its own: its samples are
    the batch's (every lane views the one array of the kernel call), with the values and
    results run_point gives, bit for bit (the stiff scheme's run is the same; the batched
    Euler lanes' lambda_max differs from the single kernel's in the last bits: test_batch)."""
    results = run_batch(REDONE, REDO_SETTINGS)
    redone = ["stiff-fallback" in r.summary.flags for r in results]
    assert sum(redone) >= 2 and not all(redone), redone  # the test means something
    block = results[0].trajectory.window.base
    # a row per run: the columns that pad the kernel's lanes to whole vectors record nothing
    assert block is not None and block.shape[0] == len(REDONE)
    for p, got, again in zip(REDONE, results, redone, strict=True):
        tr = got.trajectory
        assert tr.window.base is block and tr.mid.base is block, p
        if not again:
            continue
        want = run_point(p, REDO_SETTINGS)
        ref = want.trajectory
        np.testing.assert_equal(got.as_record() | {"runtime_s": 0}, want.as_record() | {"runtime_s": 0})
        assert tr.settings.method == ref.settings.method == "stiff", p
        assert tr.steps_done == ref.steps_done, p
        for name in ("window_t", "window", "mid_t", "mid", "trace_t", "trace", "lyap_logs"):
            assert np.array_equal(getattr(tr, name), getattr(ref, name)), (p, name)


def test_a_batch_holds_its_runs_and_one_run_more():
    """The memory a batch takes (numpy's arrays, traced) is its runs' (memory_of) and at
    most one run's more, however many lanes are re-integrated: a re-integrated lane that
    kept arrays of its own beside the batch's would take 4 runs' more here, and flags that
    concatenated every sample of a lane 2 runs' at once."""
    sizes = [memory_of(make_grid(p, REDO_SETTINGS), REDO_SETTINGS).total for p in REDONE]
    padded = sum(sizes) + -len(sizes) % VECTOR * sizes[-1]
    run_batch(REDONE[:MIN_LANES], SolverSettings(method="euler", t_end=20.0, window=10.0))
    tracemalloc.start()
    try:
        results = run_batch(REDONE, REDO_SETTINGS)
        held, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert sum("stiff-fallback" in r.summary.flags for r in results) >= 4
    assert held < padded + 0.1 * sizes[0], (held, padded)
    assert peak < padded + 1.25 * max(sizes), (peak, padded, max(sizes))


def test_moved_into_copies_a_run_into_anothers_buffers():
    s = SolverSettings(method="euler", dt=1e-3, t_end=40.0, window=10.0, lyap=True)
    a, b = simulate(Params(k=6.0), s), simulate(Params(k=9.0), s)
    assert b.buffers is not None and a.mid.shape[1] > 0  # a middle window to place too
    moved = moved_into(a, b.buffers)
    for name in ("window_t", "window", "mid_t", "mid", "trace_t", "trace", "lyap_logs"):
        assert np.array_equal(getattr(moved, name), getattr(a, name)), name
    assert np.shares_memory(moved.window, b.buffers[0]) and np.shares_memory(moved.trace, b.buffers[1])
    assert moved.final is a.final and moved.steps_done == a.steps_done
    other = simulate(Params(k=6.0), SolverSettings(method="euler", dt=1e-3, t_end=40.0, window=5.0))
    assert other.buffers is not None
    assert moved_into(a, other.buffers) is a  # another grid: kept as it is
    assert moved_into(a, a.buffers) is a  # its own


def test_sample_times_are_the_sampled_steps_times_dt():
    """The window's times, built a part at a time, are the very floats of the steps the
    sampler samples times dt (with and without a middle window, after blow-ups)."""
    for t_end, window, tau in ((40.0, 10.0, 1.0), (40.0, 25.0, 1.3636), (2e5, 1e5, 10.0)):
        s = SolverSettings(method="euler", dt=1e-3, t_end=t_end, window=window)
        g = make_grid(Params(tau=tau), s)
        steps = g.sample_steps()
        assert np.array_equal(_sample_times(g), steps * g.dt)
        win, trace = np.zeros((5, g.n_samples)), np.zeros((5, g.n_trace))
        for done in (g.n_steps, g.n_steps // 2, g.mid_start + 1, g.win_start + 1, 1):
            tr = trajectory_of(Params(tau=tau), s, g, done, win, trace, np.zeros(0), 0.0)
            last = g.n_steps if done == g.n_steps else done - 1
            n_w = int(np.count_nonzero(steps <= last))
            n_m = min(n_w, g.n_mid)
            assert np.array_equal(tr.mid_t, steps[:n_m] * g.dt), (t_end, done)
            assert np.array_equal(tr.window_t, steps[n_m:n_w] * g.dt), (t_end, done)


def test_the_sample_flags_are_those_of_all_samples_at_once():
    """The closure, uphill and negative-variance checks, block by block, flag what they
    flag over all the samples at once, wherever the bad sample is."""
    s = SolverSettings(method="euler", dt=1e-3, t_end=8000.0, window=2000.0)
    g = make_grid(Params(), s)
    assert g.n_mid > 2 * SAMPLE_BLOCK  # blocks of the middle window and the end window
    rng = np.random.default_rng(1)
    base = np.vstack([rng.normal(size=g.n_samples), rng.uniform(0.0, 1.0, g.n_samples),
                      np.ones(g.n_samples), np.ones(g.n_samples), np.zeros(g.n_samples)])
    p = Params(v=2.0)  # v + m_y > 0 for every sample of base
    trace = np.vstack([np.zeros(g.n_trace), np.ones((4, g.n_trace))])
    trace[4] = 0.0
    cases = {"none": (None, 0.0), "s_y < 0": (3, -0.5), "u too large": (4, 3.0),
             "uphill": (1, -5.0), "s_x < 0": (2, -1.0)}
    for at in (1, SAMPLE_BLOCK + 7, g.n_mid + SAMPLE_BLOCK + 3, g.n_samples - 1):
        for label, (row, value) in cases.items():
            win = base.copy()
            if row is not None:
                win[row, at] = value
            tr = trajectory_of(p, s, g, g.n_steps, win, trace.copy(), np.zeros(0), 0.0)
            states = np.concatenate((tr.trace, tr.mid, tr.window), axis=1)
            want = closure_flags(states) + uphill_flags(states, p.v)
            assert _sample_flags(tr) == want, (label, at)
            assert bool(want) == (row is not None), (label, at)  # the case flags what it should
            old = any(bool(np.any(a[3] < -1e-9 * np.maximum(1.0, np.abs(a[2]) + np.abs(a[3]))))
                      for a in (tr.trace, tr.mid, tr.window) if a.shape[1])
            assert _negative_variance(tr) == old == (label == "s_y < 0"), (label, at)
