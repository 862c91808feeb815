"""The (k, tau) plane of the certified stop's targets under both stop rules, batched as a
worker computes it: what each costs, where the certified runs stop, and every cell whose
regime or attractor differs, with its class.

    .venv/bin/python benchmarks/bench_certified_plane.py [--n 20] [--t-end 1e5] [--markdown F]

An n x n lattice over k 0.5-25, tau 0.5-20, delta 0.1, at the paper's settings with
lambda_max (Euler, dt 1e-3, window 1000). Each tau's row is one core.point.run_batch call
per rule (the batched lanes: to t_end, or each retiring at its certificate), the rules in
turns (which goes first alternates by row), CPU time (time.process_time) in one process.
A differing cell's class:

- ``certified early, window unsettled at t_end``: the certified run stopped at its
  certificate; the paper's window at t_end is not certified (its label the window's);
- ``both certified``: both runs carry a certificate and still differ (a defect);
- ``same run``: neither stopped early (the same run; a chaotic run's round-off);
- ``other``: anything else, printed whole.
"""

from __future__ import annotations

import argparse
import collections
import time

import numpy as np

from core.params import Params
from core.point import PointResult, run_batch
from core.solve import SolverSettings


def cls(long: PointResult, short: PointResult) -> str:
    """The class of a cell whose two runs differ (module docstring)."""
    t_stop, t_end = short.trajectory.t_done, short.trajectory.grid.t_end
    early = t_stop < t_end * (1 - 1e-9)
    if early and short.certificate.certified and not long.certificate.certified:
        return "certified early, window unsettled at t_end"
    if long.certificate.certified and short.certificate.certified:
        return "both certified"
    if not early:
        return "same run"
    return "other"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=20)
    ap.add_argument("--t-end", type=float, default=1e5)
    ap.add_argument("--markdown", help="also write the summary here")
    args = ap.parse_args()
    rules = {rule: SolverSettings(t_end=args.t_end, stop=rule) for rule in ("t_end", "certified")}
    warm = [Params(k=float(k), tau=2.0) for k in (2, 4, 6, 8)]
    for s in rules.values():  # compiled and imported before timing
        run_batch(warm, SolverSettings(t_end=3e3, stop=s.stop))
    ks, taus = np.linspace(0.5, 25.0, args.n), np.linspace(0.5, 20.0, args.n)
    cpu = {rule: 0.0 for rule in rules}
    stops: collections.Counter[float] = collections.Counter()
    same_regime = same_both = 0
    differ: list[str] = []
    classes: collections.Counter[str] = collections.Counter()
    for row, tau in enumerate(taus):
        points = [Params(k=float(k), tau=float(tau)) for k in ks]
        out: dict[str, list[PointResult]] = {}
        for rule in (list(rules) if row % 2 == 0 else list(reversed(rules))):
            t0 = time.process_time()
            out[rule] = run_batch(points, rules[rule])
            cpu[rule] += time.process_time() - t0
        for long, short in zip(out["t_end"], out["certified"], strict=True):
            stops[round(short.trajectory.t_done, 1)] += 1
            a, b = long.summary, short.summary
            same_regime += a.regime == b.regime
            if (a.regime, a.attractor) == (b.regime, b.attractor):
                same_both += 1
                continue
            c = cls(long, short)
            classes[c] += 1
            differ.append(f"- k {long.params.k:.4g}, tau {tau:.4g} [{c}]: t_end {a.regime}/"
                          f"{a.attractor} ({long.certificate.text[:70]}); certified "
                          f"{b.regime}/{b.attractor} at t = {short.trajectory.t_done:g} "
                          f"({short.certificate.text[:70]})")
    n = args.n * args.n
    lines = [
        f"`python benchmarks/bench_certified_plane.py --n {args.n} --t-end {args.t_end:g}` "
        f"({args.n} x {args.n}, k 0.5-25, tau 0.5-20, delta 0.1; Euler dt 1e-3, lambda_max; "
        "run_batch per tau row, CPU s in one process, a shared 2-core machine)",
        "",
        f"CPU: t_end {cpu['t_end']:.1f} s, certified {cpu['certified']:.1f} s "
        f"({cpu['certified'] / cpu['t_end']:.1%})",
        "where the certified runs stopped: " + ", ".join(
            f"t = {t:g}: {c}" for t, c in sorted(stops.items())),
        f"same regime: {same_regime} of {n} ({same_regime / n:.1%}); same regime and "
        f"attractor: {same_both} ({same_both / n:.1%})",
        "differing cells by class: " + (", ".join(f"{c}: {m}" for c, m in classes.items()) or "none"),
        *differ,
    ]
    print("\n".join(lines))
    if args.markdown:
        with open(args.markdown, "w") as f:
            f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
