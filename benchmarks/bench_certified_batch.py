"""A batch of 8 points (k 2-20, tau = 10, delta 0.1; Euler, lambda_max): run_batch at stop
t_end (the batched kernel) against the same batch at stop certified (core.point.run_batch
runs it point by point on the single kernel, each stopping at its certificate), in turns,
CPU time (time.process_time), and whether each point's regime and attractor agree.

    .venv/bin/python benchmarks/bench_certified_batch.py [--t-end 2e4] [--repeat 2]
"""

from __future__ import annotations

import argparse
import time

from core.params import Params
from core.point import run_batch
from core.solve import SolverSettings

K = (2, 4, 6, 8, 10, 12, 16, 20)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--t-end", type=float, default=2e4)
    parser.add_argument("--repeat", type=int, default=2)
    args = parser.parse_args()
    points = [Params(k=float(k), tau=10.0, delta=0.1) for k in K]
    rules = {"t_end": SolverSettings(t_end=args.t_end),
             "certified": SolverSettings(t_end=args.t_end, stop="certified")}
    run_batch(points[:2], SolverSettings(t_end=1e3))  # compiled before timing
    run_batch(points[:1], SolverSettings(t_end=3e3, stop="certified"))
    cpu: dict[str, list[float]] = {rule: [] for rule in rules}
    results = {}
    for _ in range(args.repeat):
        for rule, s in rules.items():
            t0 = time.process_time()
            results[rule] = run_batch(points, s)
            cpu[rule].append(time.process_time() - t0)
    for rule, times in cpu.items():
        print(f"{rule:<10} CPU {', '.join(f'{t:.2f}' for t in times)} s")
    print(f"certified / t_end (best of each): {min(cpu['certified']) / min(cpu['t_end']):.3f}")
    for a, b in zip(results["t_end"], results["certified"], strict=True):
        same = (a.summary.regime, a.summary.attractor) == (b.summary.regime, b.summary.attractor)
        print(f"k = {a.params.k:<4g} {a.summary.regime:<12} {a.summary.attractor:<12} "
              f"t_stop {b.as_record()['t_stop']:<8g} {'same' if same else 'DIFFERENT'}")


if __name__ == "__main__":
    main()
