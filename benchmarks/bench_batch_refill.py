"""The batched kernels with stops (core.batch._Lanes: lanes retired and refilled) against the
kernel without them, interleaved A/B in one process, CPU time (time.process_time).

Run:  python benchmarks/bench_batch_refill.py [--t-end T] [--repeat R] [--against DIR]

One group of 64 points of one tau (k 6-16, tau = 10, delta = 0.1), Euler with lambda_max at
dt = 1e-3, window t_end / 100, as a worker claims a batch:

(a) the overhead of chunking: no lane ever retires. A: the kernel without stops
    (simulate_batch; with ``--against DIR``, that of another checkout's core/, e.g. main's:
    ``git archive main | tar -x -C DIR``, and then A': this tree's); B: the same points
    with a predicate asked after every chunk that always says no (every lane's trajectory
    so far built each time).
(b) lanes retiring at a realistic time: 128 points on 64 lanes, every other one stopping
    at the second chunk end (2 % of the run, as 2e3 of the paper's 1e5 time units). A: the
    kernel without stops computes all 128 to t_end (two batches); B: with stops, a stopped
    lane takes a waiting point. Printed: CPU seconds for the 128 points and the
    throughput in point-steps per second (the steps the runs keep, whose sum is what the
    stop saves).

The run is shortened (default t_end 1e4) with CHUNK_T scaled to it (t_end / 100, the
paper's 1e3 of 1e5), so the ratios are the paper run's. Prints the median of the rounds.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

import core.batch as cb
from core.params import Params
from core.solve import SolverSettings, Trajectory, make_grid

sys.path.insert(0, str(Path(__file__).parent))
from bench_kernels import other_core


def cpu(fn: Callable[[], Any]) -> tuple[float, Any]:
    t0 = time.process_time()
    out = fn()
    return time.process_time() - t0, out


def rounds(calls: dict[str, Callable[[], list[Any]]], repeat: int) -> dict[str, list[tuple[float, int]]]:
    """Each call once per round, the order alternating: (CPU seconds, point-steps kept)."""
    for fn in calls.values():
        fn()  # compile or load
    got: dict[str, list[tuple[float, int]]] = {name: [] for name in calls}
    names = list(calls)
    for r in range(repeat):
        for name in (names if r % 2 == 0 else names[::-1]):
            t, runs = cpu(calls[name])
            got[name].append((t, sum(int(tr.steps_done) for tr in runs)))
    return got


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--t-end", type=float, default=1e4)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--against", type=Path, help="another checkout whose core/ is A in (a)")
    args = ap.parse_args()
    cb.CHUNK_T = args.t_end / 100
    s = SolverSettings(t_end=args.t_end, window=args.t_end / 100, lyap=True)
    points = [Params(k=float(k), tau=10.0) for k in np.linspace(6.0, 16.0, 64)]
    g = make_grid(points[0], s)
    c = cb.chunk_steps(g)
    print(f"tau = 10, Euler + lambda_max, dt = {g.dt:g}, t_end = {args.t_end:g}, chunk "
          f"{c * g.dt:g} time units; CPU time, median of {args.repeat} interleaved rounds; "
          f"the machine is shared", flush=True)

    if args.against:
        old = other_core(args.against)
        o_points = [old.params.Params(k=p.k, tau=p.tau) for p in points]
        o_s = old.solve.SolverSettings(t_end=args.t_end, window=args.t_end / 100, lyap=True)
        no_stop: Callable[[], list[Any]] = lambda: old.batch.simulate_batch(o_points, o_s)  # noqa: E731
        label = f"no-stop kernel of {args.against}"
    else:
        no_stop = lambda: cb.simulate_batch(points, s)  # noqa: E731
        label = "no-stop kernel (this tree)"

    def never(tr: Trajectory) -> bool:
        return False

    calls = {"A": no_stop, "B": lambda: cb._Lanes(g, points, s).run(never)}
    if args.against:  # this tree's kernel without stops, beside the other's
        calls["A'"] = lambda: cb.simulate_batch(points, s)
    got = rounds(calls, args.repeat)
    med = {k: statistics.median(t for t, _ in got[k]) for k in got}
    print(f"(a) no lane retires, 64 points: A {label} {med['A']:.3f} s; B chunked, asked every "
          f"chunk {med['B']:.3f} s", flush=True)
    for k in [k for k in ("B", "A'") if k in got]:
        ratios = [tb / ta for (ta, _), (tb, _) in zip(got["A"], got[k], strict=True)]
        print(f"    {k} / A {statistics.median(ratios):.3f} (rounds: "
              + ", ".join(f"{r:.3f}" for r in ratios) + ")", flush=True)
    if "A'" in got:
        ratios = [tb / ta for (ta, _), (tb, _) in zip(got["A'"], got["B"], strict=True)]
        print(f"    B / A' {statistics.median(ratios):.3f} (rounds: "
              + ", ".join(f"{r:.3f}" for r in ratios) + ")", flush=True)

    many = [Params(k=float(k), tau=10.0) for k in np.linspace(6.0, 16.0, 128)]
    stop_at = 2 * c

    def half(tr: Trajectory) -> bool:
        return many.index(tr.params) % 2 == 1 and tr.steps_done >= stop_at

    got = rounds({"A": lambda: cb.simulate_batch(many, s),
                  "B": lambda: cb.simulate_batch(many, s, finished=half)}, args.repeat)
    for k, what in (("A", "no stops, 2 batches of 64"), ("B", "half stop at 2 % of t_end, refilled")):
        t = statistics.median(t for t, _ in got[k])
        steps = got[k][0][1]
        print(f"(b) 128 points, {what}: {t:.3f} s CPU, {steps:.3g} point-steps kept, "
              f"{steps / t:.3g} point-steps/s", flush=True)
    ratio = statistics.median(tb / ta for (ta, _), (tb, _) in zip(got["A"], got["B"], strict=True))
    ideal = got["B"][0][1] / got["A"][0][1]
    print(f"(b) B / A CPU {ratio:.3f} (the steps' ratio, ideal: {ideal:.3f})")


if __name__ == "__main__":
    main()
