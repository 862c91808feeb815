"""What the certified stop (SolverSettings.stop = "certified", core.certified_stop) saves
per run, against the paper's protocol (stop = "t_end"), and what its tries cost.

Run:  python benchmarks/bench_certified_stop.py [--t-end T] [--rounds R] [--markdown FILE]

At the paper's settings with lambda_max (Euler, dt 1e-3, t_end 1e5, window 1000, delta 0.1)
on 10 points spread over the (k, tau) plane of the issue (k 0.5-25, tau 0.5-20: stable rest
states, cycles, multi-slip transients, near the Hopf curve), each round runs every point
under both rules (core.point.run_point, whole: integration, classification, certificate,
dt error), alternating which rule goes first and reversing the points' order every other
round, in CPU time (process_time) in one process, so that a shared machine slows both alike.
Printed per point: the median CPU time under each rule, their ratio, where the certified run
stopped, its chunks and certificate tries and their CPU time (classifying and certifying the
windows of the chunks before the stop), and whether both rules agree on regime and attractor.
Then the share of runs certified and the total time under each rule. ``--plane N``: also
an N x N lattice over the same plane (both rules, interleaved), the share of its runs
stopped early, the runs whose regime or attractor differ, and the CPU time of each rule.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from core.certified_stop import simulate_to_certificate
from core.params import Params
from core.point import run_point
from core.solve import SolverSettings

#: (k, tau) over the issue's plane; delta = 0.1 (the default).
POINTS: tuple[tuple[float, float], ...] = (
    (0.5, 0.5), (4.0, 10.0), (5.0, 2.0), (3.0, 20.0), (10.0, 10.0),
    (15.0, 5.0), (20.0, 10.0), (25.0, 20.0), (12.0, 1.0), (25.0, 0.5),
)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--t-end", type=float, default=1e5)
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--markdown", help="also write the table here")
    ap.add_argument("--plane", type=int, default=0, help="also an N x N lattice of the plane")
    args = ap.parse_args()
    rules = {rule: SolverSettings(t_end=args.t_end, stop=rule) for rule in ("t_end", "certified")}
    run_point(Params(k=10, tau=10), SolverSettings(t_end=2000, stop="certified"))  # warm: imports
    cpu: dict[tuple[float, float], dict[str, list[float]]] = {
        kt: {rule: [] for rule in rules} for kt in POINTS}
    rec: dict[tuple[float, float], dict[str, dict[str, object]]] = {kt: {} for kt in POINTS}
    for rnd in range(args.rounds):
        order = list(POINTS) if rnd % 2 == 0 else list(reversed(POINTS))
        for i, kt in enumerate(order):
            names = list(rules) if (rnd + i) % 2 == 0 else list(reversed(rules))
            for rule in names:
                t0 = time.process_time()
                r = run_point(Params(k=kt[0], tau=kt[1]), rules[rule])
                cpu[kt][rule].append(time.process_time() - t0)
                rec[kt][rule] = r.as_record()
    print(f"Euler dt 1e-3, t_end {args.t_end:g}, lambda_max, delta 0.1; median of "
          f"{args.rounds} rounds, CPU s (a shared 2-core machine)")
    head = (f"{'k':>5} {'tau':>5} {'t_end s':>8} {'cert. s':>8} {'ratio':>6} {'t_stop':>8} "
            f"{'chunks':>6} {'tries':>5} {'try s':>6}  same label  regime / certificate")
    print(head)
    rows = []
    total = {rule: 0.0 for rule in rules}
    n_cert = 0
    for kt in POINTS:
        p = Params(k=kt[0], tau=kt[1])
        st = simulate_to_certificate(p, rules["certified"])  # chunks and tries, once more
        a, b = (statistics.median(cpu[kt][rule]) for rule in rules)
        total["t_end"] += a
        total["certified"] += b
        long, short = rec[kt]["t_end"], rec[kt]["certified"]
        same = all(long[x] == short[x] for x in ("regime", "attractor"))
        n_cert += bool(short["certified"]) and float(short["t_stop"]) < float(short["t_end"])  # type: ignore[arg-type]
        said = f"{short['regime']}/{short['attractor']}; {str(short['certificate'])[:60]}"
        line = (f"{kt[0]:5g} {kt[1]:5g} {a:8.3f} {b:8.3f} {b / a:6.1%} {short['t_stop']:8.6g} "
                f"{st.chunks:6d} {st.tries:5d} {st.try_s:6.3f}  {'yes' if same else 'NO':10}  {said}")
        print(line)
        rows.append(f"| {kt[0]:g} | {kt[1]:g} | {a:.3f} | {b:.3f} | {b / a:.1%} | "
                    f"{short['t_stop']:.6g} | {st.chunks} | {st.tries} | {st.try_s:.3f} | "
                    f"{'yes' if same else 'no'} | {said.replace('|', '/')} |")
    summary = (f"certified early: {n_cert} of {len(POINTS)} runs; total {total['t_end']:.2f} s "
               f"(t_end) against {total['certified']:.2f} s (certified), "
               f"{total['certified'] / total['t_end']:.1%}")
    print(summary)
    if args.plane:
        summary += "\n\n" + plane(args.plane, rules)
        print(summary.rsplit("\n\n", 1)[1])
    if args.markdown:
        with open(args.markdown, "w") as f:
            f.write(f"`python benchmarks/bench_certified_stop.py --t-end {args.t_end:g} "
                    f"--rounds {args.rounds}` (CPU s, median; a shared 2-core machine)\n\n"
                    "| k | tau | t_end s | certified s | ratio | t_stop | chunks | tries | "
                    "try s | same label | certified run |\n"
                    "|---|---|---|---|---|---|---|---|---|---|---|\n" + "\n".join(rows)
                    + f"\n\n{summary}\n")


def plane(n: int, rules: dict[str, SolverSettings]) -> str:
    """An n x n lattice over k 0.5-25, tau 0.5-20 under both rules: what the text says."""
    total = {rule: 0.0 for rule in rules}
    early = 0
    differ = []
    for i, k in enumerate(np.linspace(0.5, 25.0, n)):
        for j, tau in enumerate(np.linspace(0.5, 20.0, n)):
            rec = {}
            for rule in (list(rules) if (i + j) % 2 == 0 else list(reversed(rules))):
                t0 = time.process_time()
                rec[rule] = run_point(Params(k=float(k), tau=float(tau)), rules[rule]).as_record()
                total[rule] += time.process_time() - t0
            long, short = rec["t_end"], rec["certified"]
            early += float(short["t_stop"]) < float(short["t_end"])  # type: ignore[arg-type]
            if (long["regime"], long["attractor"]) != (short["regime"], short["attractor"]):
                differ.append(f"k {k:.4g} tau {tau:.4g}: {long['regime']}/{long['attractor']} "
                              f"against {short['regime']}/{short['attractor']}")
    return (f"{n} x {n} lattice, k 0.5-25, tau 0.5-20: stopped early {early} of {n * n} "
            f"({early / (n * n):.0%}); regime and attractor differ in {len(differ)}"
            + "".join(f"\n- {d}" for d in differ)
            + f"\nCPU: {total['t_end']:.1f} s (t_end) against {total['certified']:.1f} s "
              f"(certified), {total['certified'] / total['t_end']:.1%}")


if __name__ == "__main__":
    main()
