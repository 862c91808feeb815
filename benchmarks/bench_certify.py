"""What certification (core.certify) costs beside the run it certifies.

Run:  python benchmarks/bench_certify.py [--t-end T] [--rounds R] [--markdown FILE]

At the paper's settings (Euler, dt 1e-3, t_end 1e5, window 1000) on a handful of points
(an orbit, a fixed point, a long transient Newton gives up on, a large-b square wave, a
long and a short delay, two sharp-slip orbits and a run whose Euler is off the model),
each round runs every point (core.point.run_point, which certifies) and then certifies it
again alone (core.certify.certify on the run's own trajectory and the window's own label,
classified again, not relabelled by the run's certificate), and beside it, in the same
round, the certification's first attempt alone ("one step": at the certifier's step,
without the retry at dt / 4 core.certify makes where that step may be what failed), in
CPU time (process_time), in one process, the points' and the contenders' order reversed
every other round so that a busy machine slows both alike. Printed per point: the median
run and certification times, their ratio (the target: at most 10 %), the first attempt's
time, and what the certificate said. The first certification in a process also pays the
import of scipy's sparse solvers and the loading of the orbit kernels from numba's cache:
measured once, before the rounds, and printed apart (a worker pays it once).
"""

from __future__ import annotations

import argparse
import statistics
import time

from core.certify import Certificate, certify
from core.classify import Summary, classify
from core.lyapunov import estimate
from core.params import Params
from core.point import run_point
from core.solve import SolverSettings, Trajectory, simulate

POINTS = {
    "k=10 tau=10 (orbit)": Params(k=10, tau=10),
    "k=4 tau=10 (fixed point)": Params(k=4, tau=10),
    "k=20 tau=10 (slow transient)": Params(k=20, tau=10),
    "b=15 k=12 tau=6 (square wave)": Params(b=15, k=12, tau=6),
    "k=7 tau=60 (long delay)": Params(k=7, tau=60),
    "k=30 tau=1 (short delay)": Params(k=30, tau=1),
    "b=22 k=12 tau=2 (period refined)": Params(b=22, k=12, tau=2),
    "b=24 k=12 tau=7.43 (Newton refined)": Params(b=24, k=12, tau=7.43),
    "k=37.6 tau=0.5 (Euler off)": Params(k=37.6, tau=0.5),
}


def first_attempt(tr: Trajectory, label: Summary) -> Certificate:
    """The certification's first attempt alone (no retry at dt / 4)."""
    return certify(tr, label, retry=False)


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
    ones: dict[str, list[float]] = {name: [] for name in POINTS}
    said: dict[str, str] = {}
    for rnd in range(args.rounds):
        names = list(POINTS) if rnd % 2 == 0 else list(reversed(POINTS))
        for name in names:
            p = POINTS[name]
            t0 = time.process_time()
            r = run_point(p, s)
            t1 = time.process_time()
            tr = r.trajectory
            lyap = estimate(tr.lyap_logs, tr.grid.renorm_interval)
            window = classify(tr.window_t, tr.window, tr.blew_up, lyap, tr.mid_t, tr.mid, p)
            t2 = time.process_time()
            contenders = [(certs, certify), (ones, first_attempt)]
            if rnd % 2:
                contenders.reverse()
            for times, how in contenders:
                c0 = time.process_time()
                c = how(tr, window)
                times[name].append(time.process_time() - c0)
                if how is certify:
                    said[name] = ("yes: " if c.certified else "no: ") + c.text[:160]
            # the run without its classification and certification (as certify's median)
            runs[name].append(t1 - t0 - (t2 - t1) - certs[name][-1])
    print(f"Euler dt 1e-3, t_end {args.t_end:g}, median of {args.rounds} rounds, CPU s")
    print(f"{'point':36} {'run':>7} {'certify':>8} {'share':>6} {'one step':>8}  certificate")
    rows = []
    for name in POINTS:
        run, cert = statistics.median(runs[name]), statistics.median(certs[name])
        one = statistics.median(ones[name])
        print(f"{name:36} {run:7.3f} {cert:8.4f} {cert / run:6.1%} {one:8.4f}  {said[name]}")
        cell = said[name].replace("|", "\\|")
        rows.append(f"| {name} | {run:.3f} | {cert:.4f} | {cert / run:.1%} | {one:.4f} | {cell} |")
    if args.markdown:
        with open(args.markdown, "w") as f:
            f.write(f"Euler dt 1e-3, t_end {args.t_end:g}, median of {args.rounds} rounds, CPU s "
                    "(`python benchmarks/bench_certify.py`; the machine shared)\n\n"
                    "| point | run | certify | share | one step | certificate |\n"
                    "|---|---:|---:|---:|---:|---|\n"
                    + "\n".join(rows) + f"\n\n{once}.\n")


if __name__ == "__main__":
    main()
