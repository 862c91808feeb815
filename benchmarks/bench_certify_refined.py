"""What the certifier's retry at dt / 4 (core.certify) changes over a friction plane: how
many runs it certifies that the first attempt did not, what each says, and what it costs.

    .venv/bin/python benchmarks/bench_certify_refined.py [--n 20] [--t-end 1e5] [--jobs 2]

The plane of the report's Fig. 8B (b 0.5-24, tau 0.1-20, k = 12, delta = 0.1; sharp slips
at large b), n x n, at the paper's settings (Euler, dt 1e-3, window 1000, lambda_max on).
Each run's window is classified as the run classifies it, then certified twice, in turns
(which goes first alternates by cell): by core.certify.certify (the first attempt and, where
that step may be what failed, the retry), and by the first attempt alone
(bench_certify.first_attempt), in CPU time (time.process_time) in the process that ran the
cell. Printed: the certified count of each, the certification CPU of each, and every cell
whose certificate differs (what the first attempt said, what the retry said), then the
retry's outcomes by kind.
"""

from __future__ import annotations

import argparse
import collections
import multiprocessing
import time

import numpy as np
from bench_certify import first_attempt  # beside this script (python puts its folder on sys.path)

from core.certify import certify
from core.classify import classify
from core.lyapunov import estimate
from core.params import Params
from core.point import run_point
from core.solve import SolverSettings

Cell = tuple[float, float, bool, bool, float, float, str, str, float]


def cell(args: tuple[float, float, float, int]) -> Cell:
    """(b, tau, refined certified, one-step certified, their CPU s, both texts, the run's
    CPU s with its own certification)."""
    b, tau, t_end, order = args
    p = Params(b=b, k=12.0, tau=tau, delta=0.1)
    r0 = time.process_time()
    r = run_point(p, SolverSettings(t_end=t_end))
    run_s = time.process_time() - r0
    tr = r.trajectory
    lyap = estimate(tr.lyap_logs, tr.grid.renorm_interval) if not tr.blew_up else None
    window = classify(tr.window_t, tr.window, tr.blew_up, lyap, tr.mid_t, tr.mid, p)
    out = {}
    hows = [certify, first_attempt] if order % 2 == 0 else [first_attempt, certify]
    for how in hows:
        c0 = time.process_time()
        c = how(tr, window)
        out[how.__name__] = (c, time.process_time() - c0)
    (new, t_new), (old, t_old) = out["certify"], out["first_attempt"]
    return b, tau, new.certified, old.certified, t_new, t_old, new.text, old.text, run_s


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=20)
    ap.add_argument("--t-end", type=float, default=1e5)
    ap.add_argument("--jobs", type=int, default=2)
    args = ap.parse_args()
    todo = [(float(b), float(tau), args.t_end, i)
            for i, (b, tau) in enumerate((b, tau) for tau in np.linspace(0.1, 20, args.n)
                                         for b in np.linspace(0.5, 24, args.n))]
    with multiprocessing.get_context("spawn").Pool(args.jobs) as pool:
        cells = pool.map(cell, todo, chunksize=1)
    new = sum(c[2] for c in cells)
    old = sum(c[3] for c in cells)
    print(f"Fig. 8B's plane, {args.n} x {args.n} (b 0.5-24, tau 0.1-20, k = 12, delta = 0.1), "
          f"Euler dt 1e-3, t_end {args.t_end:g}")
    print(f"certified: {new} of {len(cells)} with the retry, {old} by the first attempt alone")
    print(f"certification CPU: {sum(c[4] for c in cells):.2f} s with the retry, "
          f"{sum(c[5] for c in cells):.2f} s first attempts alone; the runs {sum(c[8] for c in cells):.1f} s "
          "(each with its own certification)")
    kinds: collections.Counter[str] = collections.Counter()
    for b, tau, n_ok, o_ok, t_n, t_o, n_text, o_text, _ in cells:
        if n_text == o_text:
            continue
        kind = ("certified by the retry" if n_ok and not o_ok else
                "certified by neither, said otherwise" if not n_ok and not o_ok else
                "certified by both, said otherwise" if n_ok and o_ok else
                "certified by the first attempt only")
        kinds[kind] += 1
        print(f"\nb = {b:.4g}, tau = {tau:.4g}: {kind} ({t_o * 1e3:.1f} -> {t_n * 1e3:.1f} ms)\n"
              f"  first attempt: {o_text}\n  with the retry: {n_text}")
    print()
    for kind, count in kinds.most_common():
        print(f"{count:5d}  {kind}")


if __name__ == "__main__":
    main()
