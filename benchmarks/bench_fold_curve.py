"""The fold of cycles in (k, tau), continued as a curve (core.fold_continuation) against
found tau by tau (core.fold_curve: a branch from the Hopf point walked through its turn at
each tau), and how far the two agree.

Run:  python benchmarks/bench_fold_curve.py [--rounds R] [--from-tau 10] [--to-tau 2]
          [--markdown FILE]

Each round computes, in one process and in CPU time (process_time), alternating which goes
first: the curve from its fold at --from-tau down to --to-tau, and the one-parameter folds at
the same number of evenly spaced tau as the nine of tau = 2, 3, ..., 10 (the pointwise way).
Then, at nine of the curve's own points, the one-parameter fold at the point's tau, and the
largest relative difference in k (the issue's target: 1e-4). The defaults at the paper's
d = 1e-4, RK4 dt = 0.01 (the curve keeps N = tau / dt from its largest tau, so dt <= 0.01).
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from core.fold_continuation import walk
from core.fold_curve import fold_curve, fold_of_cycles
from core.fold_start import start_at_fold
from core.params import Params
from core.stability import hopf_k


def continued(top: float, bottom: float) -> list:
    curve = start_at_fold(Params().with_(tau=top), ("k", "tau"), bottom)
    return list(walk(curve, bottom, 400))


def pointwise(taus: list[float]) -> list:
    return list(fold_curve(Params(), taus))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--from-tau", dest="top", type=float, default=10.0)
    ap.add_argument("--to-tau", dest="bottom", type=float, default=2.0)
    ap.add_argument("--markdown", help="also write the table here")
    args = ap.parse_args()
    taus = [float(t) for t in np.linspace(args.bottom, args.top, 9)]
    continued(args.top, args.top - 0.1)  # warm: compiles and imports
    cpu: dict[str, list[float]] = {"continued": [], "pointwise": []}
    curve: list = []
    for r in range(args.rounds):
        order = ("continued", "pointwise") if r % 2 == 0 else ("pointwise", "continued")
        for name in order:
            t0 = time.process_time()
            if name == "continued":
                curve = continued(args.top, args.bottom)
            else:
                pointwise(taus)
            cpu[name].append(time.process_time() - t0)
    picks = [curve[i] for i in np.linspace(0, len(curve) - 1, 9).round().astype(int)]
    worst = 0.0
    for point in picks:
        one = fold_of_cycles(Params().with_(tau=point.second,
                                            k=hopf_k(point.second, Params().F1)))
        if one.fold is not None:
            worst = max(worst, abs(point.first / one.fold - 1))
    lines = [
        f"fold of cycles in (k, tau), tau {args.top:g} -> {args.bottom:g}, "
        f"{args.rounds} rounds (median CPU s)",
        "| contender | CPU s | points |",
        "|---|---|---|",
        f"| continued curve | {statistics.median(cpu['continued']):.1f} | {len(curve)} |",
        f"| one-parameter folds, tau by tau | {statistics.median(cpu['pointwise']):.1f} | 9 |",
        "",
        f"largest relative difference in k at nine curve points against the one-parameter "
        f"fold at the same tau: {worst:.1e}",
        f"ends: k = {curve[0].first:.9f} at tau = {curve[0].second:g}, "
        f"k = {curve[-1].first:.9f} at tau = {curve[-1].second:g}",
    ]
    print("\n".join(lines))
    if args.markdown:
        with open(args.markdown, "w", encoding="utf-8") as f:
            f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
