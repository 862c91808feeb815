"""A batch of points of one tau (Euler, lambda_max, delta 0.1): core.point.run_batch at stop
t_end (the batched kernel to t_end), at stop certified (the batched lanes, each retiring at
its certificate: core.certified_stop.certified_batch), and the certified runs one by one on
the single kernel (run_point, each stopping at its certificate), in turns, CPU time
(time.process_time), and whether each point's regime and attractor agree with t_end's.

    .venv/bin/python benchmarks/bench_certified_batch.py [--t-end 2e4] [--repeat 2]
        [--tau 10] [--k 2,4,6,8,10,12,16,20]
"""

from __future__ import annotations

import argparse
import time

from core.params import Params
from core.point import run_batch, run_point
from core.solve import SolverSettings

K = (2, 4, 6, 8, 10, 12, 16, 20)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--t-end", type=float, default=2e4)
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--tau", type=float, default=10.0)
    parser.add_argument("--k", default=",".join(map(str, K)), help="comma-separated k values")
    args = parser.parse_args()
    points = [Params(k=float(k), tau=args.tau, delta=0.1) for k in args.k.split(",")]
    t_end, certified = SolverSettings(t_end=args.t_end), SolverSettings(t_end=args.t_end, stop="certified")
    contenders = {
        "t_end": lambda: run_batch(points, t_end),
        "certified lanes": lambda: run_batch(points, certified),
        "certified 1 by 1": lambda: [run_point(p, certified) for p in points],
    }
    run_batch(points[:4], SolverSettings(t_end=1e3))  # compiled before timing
    run_batch(points[:4], SolverSettings(t_end=3e3, stop="certified"))
    cpu: dict[str, list[float]] = {name: [] for name in contenders}
    results = {}
    for r in range(args.repeat):
        for name in (list(contenders) if r % 2 == 0 else list(reversed(contenders))):
            t0 = time.process_time()
            results[name] = contenders[name]()
            cpu[name].append(time.process_time() - t0)
    for name, times in cpu.items():
        print(f"{name:<17} CPU {', '.join(f'{t:.2f}' for t in times)} s  "
              f"({min(times) / min(cpu['t_end']):.3f} of t_end, best of each)")
    for a, b, c in zip(results["t_end"], results["certified lanes"], results["certified 1 by 1"],
                       strict=True):
        same = all((a.summary.regime, a.summary.attractor) == (x.summary.regime, x.summary.attractor)
                   for x in (b, c))
        stops = (b.as_record()["t_stop"], c.as_record()["t_stop"])
        print(f"k = {a.params.k:<5g} {a.summary.regime:<12} {a.summary.attractor:<12} "
              f"t_stop {stops[0]:<8g} {'(one by one: same)' if stops[0] == stops[1] else stops[1]} "
              f"{'same' if same else 'DIFFERENT'}")


if __name__ == "__main__":
    main()
