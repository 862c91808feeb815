"""ns per step of the single-trajectory kernels at the paper defaults (tau = 10, k = 10).

Run:  python benchmarks/bench_kernels.py [--steps N] [--repeat R]

Prints one line per variant (Euler, Euler+lambda_max, RK4, RK4+lambda_max): best-of-R
ns per step, ns per unit of model time, and the lambda_max overhead ratio measured in the
same run. Targets (issue 2): <= 10 ns per Euler step on one core, lambda_max <= 2x.
The kernels are compiled (or loaded from numba's cache) before timing.
"""

from __future__ import annotations

import argparse
import os
import platform
import time

import numpy as np

from core import Params, SolverSettings
from core.model import coefficients
from core.solve import KERNELS, make_grid


def time_variant(method: str, lyap: bool, n_steps: int, repeat: int) -> tuple[float, float]:
    """Best-of-repeat seconds per step, and the step size, for one kernel variant."""
    p = Params(tau=10.0, k=10.0)
    s = SolverSettings(method=method, t_end=1.0, window=1.0, lyap=lyap)
    g = make_grid(p, s)
    kernel, coef = KERNELS[method], coefficients(p)
    win, trace = np.zeros((5, 1001)), np.zeros((5, 1001))
    logs = np.zeros(n_steps // g.renorm_steps + 1)
    args = (coef, g.dt, g.n_delay)
    kernel(*args, 10, win, 0, 1, trace, 1, lyap, g.renorm_steps, logs)  # compile / load cache
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        done = kernel(*args, n_steps, win, n_steps - 100_000, 100, trace, n_steps // 1000,
                      lyap, g.renorm_steps, logs)
        best = min(best, time.perf_counter() - t0)
        assert done == n_steps, "benchmark point blew up"
    return best / n_steps, g.dt


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=float, default=2e7, help="Euler steps per timing (RK4: /10)")
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    print(f"# {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
          f"python {platform.python_version()}; tau = 10, k = 10, best of {args.repeat}")
    print(f"{'variant':<16}{'dt':>8}{'ns/step':>10}{'ns/time unit':>15}{'lyap cost':>11}")
    for method in ("euler", "rk4"):
        n = int(args.steps) if method == "euler" else int(args.steps) // 10
        plain, dt = time_variant(method, False, n, args.repeat)
        with_lyap, _ = time_variant(method, True, n, args.repeat)
        for label, sec, ratio in ((method, plain, ""), (method + "+lyap", with_lyap,
                                                        f"{with_lyap / plain:.2f}x")):
            print(f"{label:<16}{dt:>8g}{sec * 1e9:>10.2f}{sec / dt * 1e9:>15.1f}{ratio:>11}")


if __name__ == "__main__":
    main()
