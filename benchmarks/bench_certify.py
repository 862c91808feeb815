"""What certification (core.certify) costs beside the run it certifies.

Run:  python benchmarks/bench_certify.py [--t-end T] [--rounds R] [--markdown FILE]

At the paper's settings (Euler, dt 1e-3, t_end 1e5, window 1000) on a handful of points
(an orbit, a fixed point, a long transient Newton gives up on, a large-b square wave, a
long and a short delay), each round runs every point (core.point.run_point, which
certifies) and then certifies it again alone (core.certify.certify on the run's own
trajectory and label), in CPU time (process_time), in one process, the points' order
reversed every other round so that a busy machine slows both alike. Printed per point:
the median run and certification times, their ratio (the target: at most 10 %), and what
the certificate said. The first certification in a process also pays the import of
scipy's sparse solvers and the loading of the orbit kernels from numba's cache: measured
once, before the rounds, and printed apart (a worker pays it once).
"""

from __future__ import annotations

import argparse
import statistics
import time

from core.certify import certify
from core.classify import classify
from core.params import Params
from core.point import run_point
from core.solve import SolverSettings, simulate

POINTS = {
    "k=10 tau=10 (orbit)": Params(k=10, tau=10),
    "k=4 tau=10 (fixed point)": Params(k=4, tau=10),
    "k=20 tau=10 (slow transient)": Params(k=20, tau=10),
    "b=15 k=12 tau=6 (square wave)": Params(b=15, k=12, tau=6),
    "k=7 tau=60 (long delay)": Params(k=7, tau=60),
    "k=30 tau=1 (short delay)": Params(k=30, tau=1),
}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--t-end", type=float, default=1e5)
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--markdown", help="also write the table here (benchmarks/results/certify.md)")
    args = ap.parse_args()
    s = SolverSettings(t_end=args.t_end)
    # the first certification in this process, on a run not yet certified (run_point
    # certifies): it imports scipy's sparse solvers and loads the orbit kernels
    p = Params(k=10, tau=10)
    warm = simulate(p, SolverSettings(t_end=2000))
    label = classify(warm.window_t, warm.window, warm.blew_up, None, warm.mid_t, warm.mid, p)
    c0 = time.process_time()
    certify(warm, label)
    first = time.process_time()
    warm_twice = certify(warm, label)
    again = time.process_time()
    once = (f"first certification in a process: {first - c0:.3f} s CPU (the next: "
            f"{again - first:.3f} s; {warm_twice.certified})")
    print(once)
    runs: dict[str, list[float]] = {name: [] for name in POINTS}
    certs: dict[str, list[float]] = {name: [] for name in POINTS}
    said: dict[str, str] = {}
    for rnd in range(args.rounds):
        names = list(POINTS) if rnd % 2 == 0 else list(reversed(POINTS))
        for name in names:
            t0 = time.process_time()
            r = run_point(POINTS[name], s)
            t1 = time.process_time()
            c = certify(r.trajectory, r.summary)
            t2 = time.process_time()
            runs[name].append(t1 - t0 - (t2 - t1))   # the run without its certification
            certs[name].append(t2 - t1)
            said[name] = ("yes: " if c.certified else "no: ") + c.text[:100]
    print(f"Euler dt 1e-3, t_end {args.t_end:g}, median of {args.rounds} rounds, CPU s")
    print(f"{'point':32} {'run':>8} {'certify':>8} {'share':>7}  certificate")
    rows = []
    for name in POINTS:
        run, cert = statistics.median(runs[name]), statistics.median(certs[name])
        print(f"{name:32} {run:8.3f} {cert:8.4f} {cert / run:7.1%}  {said[name]}")
        cell = said[name].replace("|", "\\|")
        rows.append(f"| {name} | {run:.3f} | {cert:.4f} | {cert / run:.1%} | {cell} |")
    if args.markdown:
        with open(args.markdown, "w") as f:
            f.write(f"Euler dt 1e-3, t_end {args.t_end:g}, median of {args.rounds} rounds, CPU s "
                    "(`python benchmarks/bench_certify.py`; the machine shared)\n\n"
                    "| point | run | certify | share | certificate |\n|---|---:|---:|---:|---|\n"
                    + "\n".join(rows) + f"\n\n{once}.\n")


if __name__ == "__main__":
    main()
