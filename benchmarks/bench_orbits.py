"""What an orbit and a branch cost against simulating the same points the paper's way.

In one process, CPU time (time.process_time), contenders interleaved:
  - one orbit with its ten leading Floquet multipliers (core.periodic_orbit.find_orbit:
    a seed simulation to t = 3000 with RK4, Newton-Krylov, Arnoldi), against
  - one run to t = 1e5 at the paper's settings (Euler, dt = 1e-3, with lambda_max:
    core.point.run_point), at the same point;
and a branch of 100 points (core.continuation from the orbit at k = 10, tau = 10, each
point with six multipliers) against 100 such runs (timed on SIM_SAMPLE runs and scaled:
the runs' cost does not depend on the point).

    .venv/bin/python benchmarks/bench_orbits.py [--repeat 3]
"""

from __future__ import annotations

import argparse
import statistics
import time

from core.continuation import Branch, walk
from core.orbit import PeriodMap
from core.params import Params
from core.periodic_orbit import find_orbit
from core.point import run_point
from core.shooting import Solution
from core.solve import SolverSettings

POINTS = [dict(k=10.0, tau=10.0), dict(k=20.0, tau=5.0), dict(k=12.0, tau=2.0)]
SIM_SAMPLE = 3


def cpu(f) -> float:
    t0 = time.process_time()
    f()
    return time.process_time() - t0


def branch_of_100() -> None:
    p = Params(k=10.0, tau=10.0)
    o = find_orbit(p)
    shot = PeriodMap(p, o.grid).shoot(o.z, o.period)
    b = Branch.from_orbit(p, o.grid, "k", Solution(o.z, o.period, shot, 0, 0.0, 0), 1.0, 0.05, 0.3)
    n = sum(1 for _ in walk(b, lambda pt: False, 100, 1e-7))
    assert n == 100, n


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    find_orbit(Params(k=10.0, tau=10.0))  # compile and warm the kernels first
    run_point(Params(k=10.0, tau=10.0), SolverSettings(t_end=100.0))
    for kw in POINTS:
        p = Params(**kw)
        orbit_s, sim_s = [], []
        for _ in range(args.repeat):  # interleaved
            orbit_s.append(cpu(lambda p=p: find_orbit(p)))
            sim_s.append(cpu(lambda p=p: run_point(p, SolverSettings())))
        o, s = statistics.median(orbit_s), statistics.median(sim_s)
        print(f"{kw}: orbit + multipliers {o:.2f} s, paper's run to 1e5 {s:.2f} s "
              f"(ratio {s / o:.1f}x)", flush=True)
    branch_s, sim_s = [], []
    for _ in range(args.repeat):
        branch_s.append(cpu(branch_of_100))
        sim_s.append(cpu(lambda: [run_point(Params(k=10.0 + 0.3 * i, tau=10.0), SolverSettings())
                                  for i in range(SIM_SAMPLE)]) * 100 / SIM_SAMPLE)
    b, s = statistics.median(branch_s), statistics.median(sim_s)
    print(f"branch of 100 points (k from 10, tau = 10, 6 multipliers each) {b:.1f} s; "
          f"100 paper runs {s:.0f} s (from {SIM_SAMPLE}, scaled; ratio {s / b:.0f}x)")


if __name__ == "__main__":
    main()
