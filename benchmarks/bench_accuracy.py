"""The accuracy estimate's cost (core.accuracy) against a paper-settings run.

Run:  python benchmarks/bench_accuracy.py [--t-end T] [--rounds R] [--markdown FILE]

Per point, a paper-settings run (Euler, dt = 1e-3, t_end = 1e5, lambda_max on: core.solve
.simulate, then core.classify through core.point.analyse's steps) and its estimate
(core.accuracy.dt_error: the two shadows and their analysis), timed in CPU time
(process_time) in one process, interleaved round by round, so that a busy machine slows
both alike. A batch of four lanes (core.batch, tau = 0.5) is timed the same way: its
lanes' integration is cheaper per step than the single kernel's, so the estimate's share
is larger there. Printed: the median over the rounds of each, and the estimate's share of
the run. Kernels are compiled (or loaded from numba's cache) before timing.
"""

from __future__ import annotations

import argparse
import platform
import statistics
import time
from pathlib import Path

from core.accuracy import dt_error
from core.batch import simulate_batch
from core.classify import classify
from core.lyapunov import estimate
from core.params import Params
from core.solve import SolverSettings, Trajectory, simulate

POINTS = (("the paper's orbit", Params(k=10.0, tau=10.0)),
          ("a fast orbit", Params(k=40.0, tau=0.5)),
          ("a long delay", Params(k=20.0, tau=60.0)),
          ("at rest", Params(k=4.0, tau=10.0)))
LANES = tuple(Params(k=k, tau=0.5) for k in (38.0, 39.0, 40.0, 41.0))


def timed_estimate(tr: Trajectory) -> tuple[float, float]:
    """CPU seconds of the run's own analysis (lambda_max and the classifier) and of the
    estimate, and the estimate's value."""
    t0 = time.process_time()
    lyap = estimate(tr.lyap_logs, tr.grid.renorm_interval) if tr.settings.lyap else None
    summary = classify(tr.window_t, tr.window, tr.blew_up, lyap, tr.mid_t, tr.mid, tr.params)
    t1 = time.process_time()
    e = dt_error(tr, summary)
    return t1 - t0, time.process_time() - t1, e.value


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--t-end", type=float, default=1e5)
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--markdown", type=Path)
    args = ap.parse_args()
    s = SolverSettings(t_end=args.t_end)
    warm = SolverSettings(t_end=20.0, window=10.0)
    for _, p in POINTS:  # compile or load every kernel the timing uses
        timed_estimate(simulate(p, warm))
    simulate_batch(LANES, warm)
    runs: dict[str, list[float]] = {}
    costs: dict[str, list[float]] = {}
    values: dict[str, float] = {}
    for _ in range(args.rounds):
        for name, p in POINTS:
            t0 = time.process_time()
            tr = simulate(p, s)
            run = time.process_time() - t0
            analysis, cost, values[name] = timed_estimate(tr)
            runs.setdefault(name, []).append(run + analysis)
            costs.setdefault(name, []).append(cost)
            del tr
        t0 = time.process_time()
        lanes = simulate_batch(LANES, s)
        run = time.process_time() - t0
        cost = 0.0
        for tr in lanes:
            analysis, c, values["batch"] = timed_estimate(tr)
            run += analysis
            cost += c
        runs.setdefault("batch", []).append(run)
        costs.setdefault("batch", []).append(cost)
        del lanes
    rows = [f"| run (Euler, dt 1e-3, t_end {args.t_end:g}) | run, CPU s | estimate, CPU s | share "
            "| dt_error |", "|---|---:|---:|---:|---:|"]
    labels = {**{name: f"{name}: k = {p.k:g}, τ = {p.tau:g}" for name, p in POINTS},
              "batch": "4 batched lanes, τ = 0.5, k = 38-41"}
    for name in (*(n for n, _ in POINTS), "batch"):
        run, cost = statistics.median(runs[name]), statistics.median(costs[name])
        rows.append(f"| {labels[name]} | {run:.2f} | {cost:.3f} | {100 * cost / run:.1f} % | "
                    f"{values[name]:.2g} |")
    table = "\n".join(rows) + (f"\n\n{platform.processor() or platform.machine()}, "
                               f"median of {args.rounds} interleaved rounds, the machine "
                               "shared with other jobs (benchmarks/bench_accuracy.py).\n")
    print(table)
    if args.markdown:
        args.markdown.write_text(table)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
