"""The cost of run --spectrum N against a run with lambda_max alone (core.spectrum).

    .venv/bin/python benchmarks/bench_spectrum.py --repeat 3 --markdown benchmarks/results/spectrum.md

At k = tau = 10 (the periodic orbit), t_end = 2000, for Euler (dt = 1e-3) and RK4 (dt =
1e-2): the run's own kernel with lambda_max (core.solve.simulate), and the spectrum's
second pass (core.tangents) with N = 1, 2, 4, 8 tangents. The cases alternate within each
repeat in one process (the machine is shared), each timed in CPU time
(time.process_time); the best of the repeats is kept. The kernels are compiled first.
"""

from __future__ import annotations

import argparse
import time

from core.params import Params
from core.solve import SolverSettings, make_grid, simulate
from core.spectrum import spectrum

POINT = Params(k=10.0, tau=10.0)
COUNTS = (1, 2, 4, 8)
METHODS = ("euler", "rk4")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--t-end", type=float, default=2000.0)
    ap.add_argument("--markdown", help="write the table here")
    args = ap.parse_args()
    settings = {m: SolverSettings(method=m, t_end=args.t_end) for m in METHODS}
    for m in METHODS:  # compile
        short = SolverSettings(method=m, t_end=20.0)
        simulate(POINT, short)
        spectrum(POINT, short, 2)
    best: dict[tuple[str, int], float] = {}
    for _ in range(args.repeat):
        for m in METHODS:
            s = settings[m]
            for n in (0, *COUNTS):
                t0 = time.process_time()
                if n == 0:
                    simulate(POINT, s)
                else:
                    spectrum(POINT, s, n)
                cpu = time.process_time() - t0
                key = (m, n)
                best[key] = min(best.get(key, cpu), cpu)
    lines = ["| ns per step | λmax run | " + " | ".join(f"spectrum {n}" for n in COUNTS)
             + " | per exponent (slope) |",
             "|---|---:|" + "---:|" * len(COUNTS) + "---:|"]
    for m in METHODS:
        steps = make_grid(POINT, settings[m]).n_steps
        ns = {n: 1e9 * best[(m, n)] / steps for n in (0, *COUNTS)}
        slope = (ns[COUNTS[-1]] - ns[COUNTS[0]]) / (COUNTS[-1] - COUNTS[0])
        lines.append(f"| {m} | {ns[0]:.1f} | " + " | ".join(f"{ns[n]:.1f}" for n in COUNTS)
                     + f" | {slope:.1f} ({slope / ns[0]:.2f} λmax runs) |")
    table = "\n".join(lines) + "\n"
    print(table, end="")
    if args.markdown:
        with open(args.markdown, "w") as f:
            f.write(table)


if __name__ == "__main__":
    main()
