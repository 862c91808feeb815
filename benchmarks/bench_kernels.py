"""ns per point-step of the kernels, single-trajectory and batched, on one core.

Run:  python benchmarks/bench_kernels.py [--t-end T] [--repeat R]

The same 64 parameter points for every variant: k from 6 to 16 times 8 delays tau from 5 to
15, half of them off the dt grid (so the lanes have different ring-buffer lengths and step
sizes), default friction (eq. 8). Each run is integrated to t_end with the analysis window
at the paper's share of the run (1%) and the usual 2000-point trace. Printed per variant:
best-of-R ns per point-step (time / total steps of all points), ns per unit of model time,
and the batched kernel's speed-up over the single kernel measured in the same run.
Targets (issue 6): batched Euler <= 3 ns per point-step, <= 6 ns with lambda_max.
Kernels are compiled (or loaded from numba's cache) before timing.
"""

from __future__ import annotations

import argparse
import os
import platform
import time
from collections.abc import Callable

import numpy as np

from core import Params, SolverSettings, simulate
from core.batch import LANES, simulate_batch

POINTS = [Params(k=float(k), tau=float(tau)) for k in np.linspace(6.0, 16.0, 8)
          for tau in (5.0, 6.4321, 7.5, 8.8765, 10.0, 11.2345, 12.5, 15.0)]


def best_time(run: Callable[[], int], repeat: int) -> tuple[float, int]:
    """Best-of-repeat seconds of run(), and the steps it integrated."""
    best, steps = float("inf"), 0
    for _ in range(repeat):
        t0 = time.perf_counter()
        steps = run()
        best = min(best, time.perf_counter() - t0)
    return best, steps


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--t-end", type=float, default=2000.0, help="model time per run (Euler; "
                    "RK4 runs 10x longer at its 10x larger step)")
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    print(f"# {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
          f"python {platform.python_version()}; {len(POINTS)} points (k x tau, 8 ring "
          f"lengths), {LANES} slots per batch; best of {args.repeat}")
    print(f"{'variant':<22}{'dt':>7}{'ns/point-step':>15}{'ns/time unit':>14}{'speed-up':>10}")
    for method in ("euler", "rk4"):
        t_end = args.t_end * (1 if method == "euler" else 10)
        for lyap in (False, True):
            s = SolverSettings(method=method, t_end=t_end, window=t_end / 100, lyap=lyap)
            simulate(POINTS[0], SolverSettings(method=method, t_end=1.0, window=1.0,
                                               lyap=lyap))
            simulate_batch(POINTS[:2], SolverSettings(method=method, t_end=1.0, window=1.0,
                                                      lyap=lyap))
            single, n = best_time(lambda s=s: sum(simulate(p, s).steps_done for p in POINTS),
                                  args.repeat)
            batched, n_b = best_time(
                lambda s=s: sum(t.steps_done for t in simulate_batch(POINTS, s)), args.repeat)
            assert n == n_b
            dt = s.step
            name = method + ("+lyap" if lyap else "")
            for label, sec, ratio in ((f"{name} single", single, ""),
                                      (f"{name} batched", batched, f"{single / batched:.2f}x")):
                ns = sec / n * 1e9
                print(f"{label:<22}{dt:>7g}{ns:>15.2f}{ns / dt:>14.1f}{ratio:>10}")


if __name__ == "__main__":
    main()
