"""The job queue's overhead per job, and the worker pool's scaling from 1 to 2 workers.

Run:  python benchmarks/bench_queue.py [--jobs N] [--runs M] [--t-end T]

1. Overhead: N jobs on a SQLite file (WAL), one process doing what a worker does per job
   besides computing: claim (UPDATE ... RETURNING in BEGIN IMMEDIATE), look up the cache,
   write the result (guarded UPDATE). Prints mean, median and p95 ms per job. Then the
   same with two processes contending for the same file. Target: <= 5 ms.
2. Scaling: the same compute-bound sweep (M Euler runs with lambda_max to t_end = T, on
   fresh databases so nothing is cached) through `slopetui worker -j 1` and `-j 2`.
   Throughput is runs / (last result - first claim), from the workers' log, so pool
   start-up is not counted. Target: 2 workers >= 1.8x the throughput of 1.
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import os
import platform
import re
import statistics
import subprocess
import sys
import tempfile
import time
from datetime import datetime
from pathlib import Path

from core.params import Params
from core.point import run_point
from core.solve import SolverSettings
from slopetui.queue import jobs
from slopetui.store.open import open_store
from slopetui.sweeps.spec import parse_spec
from slopetui.sweeps.submit import submit

CHEAP = {"method": "rk4", "dt": 0.01, "t_end": 200.0, "window": 100.0}


def _spec(n: int, solver: dict[str, object]) -> object:
    return parse_spec({"x": {"param": "k", "start": 4, "stop": 12, "num": n},
                       "fixed": {"tau": 2.0}, "solver": solver})


def overhead_worker(url: str, worker_id: str, out: mp.Queue) -> None:
    """Claim, cache lookup and result write until the queue is empty; per-job seconds."""
    db = open_store(url)
    record = run_point(Params(tau=2.0), SolverSettings(**CHEAP)).as_record()
    times = []
    while True:
        t0 = time.perf_counter()
        # one run claimed and begun: the batch claim with a batch of 1
        batch = jobs.begin(db, jobs.claim_batch(db, worker_id, 1), worker_id)
        if not batch:
            break
        job = batch[0]
        jobs.cached_result(db, job)
        jobs.complete(db, job, worker_id, record)
        times.append(time.perf_counter() - t0)
    out.put(times)


def measure_overhead(folder: Path, n_jobs: int, n_procs: int) -> list[float]:
    url = f"sqlite:///{folder / f'overhead-{n_procs}.db'}"
    db = open_store(url)
    submit(db, _spec(n_jobs, CHEAP))
    ctx = mp.get_context("spawn")
    out = ctx.Queue()
    procs = [ctx.Process(target=overhead_worker, args=(url, f"bench-{i}", out))
             for i in range(n_procs)]
    for p in procs:
        p.start()
    times = [t for _ in procs for t in out.get()]
    for p in procs:
        p.join()
    assert len(times) == n_jobs, (len(times), n_jobs)
    return times


def report_overhead(label: str, times: list[float]) -> None:
    ms = sorted(1e3 * t for t in times)
    p95 = ms[int(0.95 * (len(ms) - 1))]
    print(f"  {label:34} mean {statistics.mean(ms):6.2f} ms   median {statistics.median(ms):6.2f}"
          f" ms   p95 {p95:6.2f} ms   ({len(ms)} jobs)")


STAMP = re.compile(r"^(\d{4}-\d\d-\d\d \d\d:\d\d:\d\d,\d{3}) \d+ INFO (.*)$", re.MULTILINE)


def pool_throughput(folder: Path, workers: int, n_runs: int, t_end: float) -> tuple[float, float]:
    """(runs per second, wall seconds of the whole command) for one pool size."""
    url = f"sqlite:///{folder / f'scaling-{workers}.db'}"
    submit(open_store(url), _spec(n_runs, {"method": "euler", "t_end": t_end, "window": 100.0}))
    log = folder / f"scaling-{workers}.log"
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-m", "slopetui", "worker", "-j", str(workers),
                    "--exit-when-idle", "--db", url, "--log", str(log)], check=True)
    wall = time.perf_counter() - t0
    events = [(datetime.strptime(ts, "%Y-%m-%d %H:%M:%S,%f"), msg)
              for ts, msg in STAMP.findall(log.read_text())]
    started = [t for t, msg in events if msg.startswith("worker ") and msg.endswith("started")]
    done = [t for t, msg in events if re.match(r"run \d+ done", msg)]
    assert len(done) == n_runs, f"{len(done)} of {n_runs} runs done"
    return n_runs / (max(done) - min(started)).total_seconds(), wall


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--jobs", type=int, default=1000, help="jobs for the overhead test")
    ap.add_argument("--runs", type=int, default=24, help="runs for the scaling test")
    ap.add_argument("--t-end", type=float, default=2e4,
                    help="t_end of each scaling run (Euler, dt 1e-3, with lambda_max)")
    args = ap.parse_args()
    print(f"machine: {platform.processor() or platform.machine()}, "
          f"{len(os.sched_getaffinity(0))} cores, Python {platform.python_version()}")
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        print("queue overhead per job (claim + cache lookup + result write), SQLite WAL:")
        report_overhead("1 process", measure_overhead(folder, args.jobs, 1))
        report_overhead("2 processes on one file", measure_overhead(folder, args.jobs, 2))
        print(f"pool scaling: {args.runs} Euler runs with lambda_max, t_end = {args.t_end:g}:")
        one, wall1 = pool_throughput(folder, 1, args.runs, args.t_end)
        two, wall2 = pool_throughput(folder, 2, args.runs, args.t_end)
        print(f"  1 worker : {one:6.3f} runs/s  ({wall1:5.1f} s wall with start-up)")
        print(f"  2 workers: {two:6.3f} runs/s  ({wall2:5.1f} s wall with start-up)")
        print(f"  speed-up : {two / one:.2f}x  (wall with start-up: {wall1 / wall2:.2f}x)")


if __name__ == "__main__":
    main()
