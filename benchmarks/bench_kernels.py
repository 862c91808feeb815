"""ns per point-step of the batched kernels against the yardstick and the single kernels.

Run:  python benchmarks/bench_kernels.py [--t-end T] [--repeat R] [--processes P]
          [--markdown FILE] [--small-groups FILE]

A (k, tau) plane of 64 k values (6 to 16) times 3 delays (5, 6.4321 off the dt grid, 10):
three groups of 64 lanes that share tau, as the workers claim them. Per variant (Euler and
RK4, with and without lambda_max), three contenders, timed in CPU time (process_time) in
one process and interleaved round by round (each round in another order), so that a busy
machine slows all of them alike:

* yardstick: the minimal kernel of the same shape (benchmarks/yardstick.py) on each group;
* batched: core.batch.simulate_batch on all 192 points, with the analysis window at the
  paper's share of the run (1%, and as long a window at the middle) and a 2000-point trace;
* single: core.solve.simulate, run by run, on 8 points per tau.

Printed: the median ns per point-step of each, the median of the rounds' batched /
yardstick ratios, and the batched speed-up over the single kernel with the same lambda
setting. The targets: Euler and Euler + lambda_max batched within 1.25x of the
yardstick; RK4 and RK4 + lambda_max batched >= 4x faster than the single RK4.
Kernels are compiled (or loaded from numba's cache) before timing.

Everything is timed in a thread of its own, as a worker computes its runs (the compute
thread of slopetui.queue.worker_process). In a process's main thread the batched RK4 +
lambda_max kernel ran at a speed drawn anew for each process: within one process its
rounds agree within a few per cent, but from one process to the next it measured 9.2 to
14.1 ns per point-step (the machine otherwise idle) while the yardstick stayed within
9.3-10.4. In a thread it measured 8.9-10.3 in the same processes (8 processes, the
plane's 192 points, best of 2, interleaved: main thread 9.7-12.1). The main thread's
stack starts at a random offset within its page (address space randomisation), a
thread's at a page boundary, and the fused loop keeps its stages in registers and
spills many of them to the stack (1,900 stack accesses in its code). Moving the state
and the rings within their page moved the time by up to 10% but left the slow processes
slow, and so did moving the heap; running the same call in a new thread made each fast
again (11.2-12.9 -> 9.5-10.0 in three slow processes of eight): the stack's offset is
the cause. Presumably 4K aliasing between the spills and the rows of the state and the
rings, which cover every offset of a page (core.batch.SKEW); the machine's virtual CPUs
have no hardware counters to confirm it.

``--processes P`` measures every variant in P fresh processes, one after another, and
prints the median of their figures with the range (low-high) of the ratios over them.

``--small-groups FILE`` also times groups of 2 to 5 points of one tau (tau = 10), the
batches an adaptive sweep's refined levels make, against the single kernel, in ns per
point-step (best of 3): where core.batch.MIN_LANES comes from.

``--against DIR`` instead times this tree's kernels against those of another checkout's
core/ (e.g. ``git archive main | tar -x -C DIR``), interleaved A/B in one process and one
thread, CPU time: the batched kernels on 64 lanes (k 6-16, tau = 10), the single kernels
(core.solve.simulate) on 4 points (k, tau) = (10, 10), (12, 6.4321), (6, 5), (8, 1), and
with ``--spectrum`` core.spectrum's tangent kernels with N = 2; it prints the median ns
per step of each and the median of the rounds' new / old ratios. The other core/ is
copied under the package name ``core_against``.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Callable
from functools import partial
from pathlib import Path
from typing import Any, TypeVar

import numpy as np
import yardstick  # beside this script (python puts the script's folder on sys.path)

from core.batch import simulate_batch
from core.model import coefficients
from core.params import Params
from core.solve import SolverSettings, make_grid, simulate

TAUS = (5.0, 6.4321, 10.0)
POINTS = [Params(k=float(k), tau=tau) for tau in TAUS for k in np.linspace(6.0, 16.0, 64)]
SINGLE = [p for i, p in enumerate(POINTS) if i % 8 == 0]  # 8 per tau
VARIANTS = (("euler", False), ("euler", True), ("rk4", False), ("rk4", True))
TARGET_RATIO = 1.25
TARGET_SPEEDUP = 4.0
T = TypeVar("T")


def settings(method: str, lyap: bool, t_end: float) -> SolverSettings:
    """The variant's settings: Euler at dt 1e-3 to t_end, RK4 at dt 1e-2 to 10 t_end."""
    t = t_end if method == "euler" else 10 * t_end
    return SolverSettings(method=method, t_end=t, window=t / 100, lyap=lyap)


def contenders(method: str, lyap: bool, s: SolverSettings) -> dict[str, Callable[[], int]]:
    """Each contender as a call returning the point-steps it integrated."""
    kernel = getattr(yardstick, method)
    groups = []
    for tau in TAUS:
        members = [p for p in POINTS if p.tau == tau]
        g = make_grid(members[0], s)
        groups.append((np.stack([coefficients(p) for p in members]), g.dt, g.n_delay, g.n_steps))

    def run_yardstick() -> int:
        for coef, dt, n_delay, n_steps in groups:
            kernel(coef, dt, n_delay, n_steps, lyap)
        return sum(c.shape[0] * n for c, _, _, n in groups)

    def run_batched() -> int:
        return sum(t.steps_done for t in simulate_batch(POINTS, s))

    def run_single() -> int:
        return sum(simulate(p, s).steps_done for p in SINGLE)

    return {"yardstick": run_yardstick, "batched": run_batched, "single": run_single}


def as_workers_run(fn: Callable[[], T]) -> T:
    """fn() in a thread of its own, as a worker computes its runs (see the docstring)."""
    out: list[T] = []
    errors: list[BaseException] = []

    def target() -> None:
        try:
            out.append(fn())
        except BaseException as exc:  # re-raised in the caller's thread
            errors.append(exc)

    thread = threading.Thread(target=target, name="compute")
    thread.start()
    thread.join()
    if errors:
        raise errors[0]
    return out[0]


def warm_up(method: str, lyap: bool) -> None:
    """Compile (or load) every kernel of the variant before timing it."""
    s = SolverSettings(method=method, t_end=1.0, window=1.0, lyap=lyap)
    coef = np.stack([coefficients(p) for p in POINTS[:2]])
    getattr(yardstick, method)(coef, s.step, 10, 20, lyap)
    simulate_batch(POINTS[:2], s)
    simulate(POINTS[0], s)


def measure(method: str, lyap: bool, t_end: float, repeat: int) -> dict[str, float]:
    """Median ns per point-step of each contender, the median batched/yardstick ratio and
    the median single/batched speed-up, over ``repeat`` interleaved rounds."""
    warm_up(method, lyap)
    calls = contenders(method, lyap, settings(method, lyap, t_end))
    ns: dict[str, list[float]] = {name: [] for name in calls}
    names = list(calls)
    for r in range(repeat):  # each round in another order: no contender always runs first
        for name in names[r % len(names):] + names[:r % len(names)]:
            t0 = time.process_time()
            steps = calls[name]()
            ns[name].append((time.process_time() - t0) / steps * 1e9)
    ratios = [b / y for b, y in zip(ns["batched"], ns["yardstick"], strict=True)]
    speedups = [s / b for s, b in zip(ns["single"], ns["batched"], strict=True)]
    return {**{name: statistics.median(v) for name, v in ns.items()},
            "ratio": statistics.median(ratios), "speedup": statistics.median(speedups)}


def best_ns(call: Callable[[], object], point_steps: int) -> float:
    """Best of 3 CPU times of call(), in ns per point-step."""
    times = []
    for _ in range(3):
        t0 = time.process_time()
        call()
        times.append(time.process_time() - t0)
    return min(times) / point_steps * 1e9


def small_groups(t_end: float) -> list[str]:
    """Single kernel against kernel calls on groups of 2-5 points (core.batch._integrate,
    padded to whole vectors), ns per point-step, best of 3, as a Markdown table."""
    from core.batch import _integrate  # the one call, below simulate_batch's MIN_LANES rule
    out = ["| ns per point-step | single kernel | batch of 2 | 3 | 4 | 5 |",
           "|---|---:|---:|---:|---:|---:|"]
    for method, lyap in VARIANTS:
        s = settings(method, lyap, t_end)
        points = [Params(k=6.0 + i, tau=10.0) for i in range(5)]
        g = make_grid(points[0], s)
        warm_up(method, lyap)

        cells = [best_ns(partial(simulate, points[0], s), g.n_steps)]
        cells += [best_ns(partial(_integrate, g, points[:n], s), n * g.n_steps)
                  for n in (2, 3, 4, 5)]
        name = method + (" + λmax" if lyap else "")
        out.append(f"| {name} | " + " | ".join(f"{c:.1f}" for c in cells) + " |")
        print(out[-1], flush=True)
    return out


def table(rows: list[tuple[str, dict[str, Any]]]) -> list[str]:
    """The figures as a Markdown table (with the ratios' ranges over processes, if any:
    ``ratio_range``, ``speedup_range``)."""
    out = ["| variant | yardstick, ns/point-step | batched | single | batched / yardstick "
           "| batched speed-up over single | target |",
           "|---|---:|---:|---:|---:|---:|---|"]
    for name, m in rows:
        if name.startswith("euler"):
            target = f"ratio ≤ {TARGET_RATIO}: " + ("met" if m["ratio"] <= TARGET_RATIO else "**not met**")
        else:
            target = f"speed-up ≥ {TARGET_SPEEDUP:g}×: " + (
                "met" if m["speedup"] >= TARGET_SPEEDUP else "**not met**")
        ratio, speedup = f"{m['ratio']:.2f}×", f"{m['speedup']:.1f}×"
        if "ratio_range" in m:
            ratio += " ({:.2f}–{:.2f})".format(*m["ratio_range"])
            speedup += " ({:.1f}–{:.1f})".format(*m["speedup_range"])
        out.append(f"| {name} | {m['yardstick']:.2f} | **{m['batched']:.2f}** | {m['single']:.2f} "
                   f"| {ratio} | {speedup} | {target} |")
    return out


def in_processes(n: int, t_end: float, repeat: int) -> list[tuple[str, dict[str, Any]]]:
    """Every variant measured in n fresh processes (--child), one after another: the median
    of each figure over them, and the ratios' ranges."""
    runs = []
    for i in range(n):
        out = subprocess.run([sys.executable, __file__, "--child", "--t-end", str(t_end),
                              "--repeat", str(repeat)], check=True, capture_output=True,
                             text=True).stdout
        runs.append(json.loads(out.splitlines()[-1]))
        print(f"# process {i + 1}: " + ", ".join(
            f"{name} {m['batched']:.2f} ns ({m['ratio']:.2f}×, {m['speedup']:.1f}×)"
            for name, m in runs[-1]), flush=True)
    rows = []
    for v, (name, _) in enumerate(runs[0]):
        figures = [run[v][1] for run in runs]
        m: dict[str, Any] = {key: statistics.median(f[key] for f in figures) for key in figures[0]}
        for key in ("ratio", "speedup"):
            m[f"{key}_range"] = (min(f[key] for f in figures), max(f[key] for f in figures))
        rows.append((name, m))
    return rows


#: --against: the points, and model time per run of each variant (~1e6 steps).
AGAINST_POINTS = ((10.0, 10.0), (12.0, 6.4321), (6.0, 5.0), (8.0, 1.0))
AGAINST_T = {"euler": 700.0, "rk4": 2000.0, "stiff": 400.0}


def other_core(tree: Path) -> Any:
    """DIR/core imported as the package ``core_against`` (its imports of core rewritten)."""
    folder = Path(tempfile.mkdtemp(prefix="bench-against-"))
    shutil.copytree(tree / "core", folder / "core_against")
    for path in (folder / "core_against").glob("*.py"):
        text = re.sub(r"\b(from|import) core(\.| import)", r"\1 core_against\2", path.read_text())
        path.write_text(text)
    sys.path.insert(0, str(folder))
    import core_against.batch
    import core_against.params
    import core_against.solve
    import core_against.spectrum
    return core_against


def one_call(pkg: Any, fn: Callable[..., Any], method: str, lyap: bool, run: bool, k: float,
             tau: float, t: float) -> int:
    """One run (``run``) or spectrum of N = 2 with package pkg's ``fn``: the steps taken."""
    p = pkg.params.Params(k=k, tau=tau)
    s = pkg.solve.SolverSettings(method=method, t_end=t, window=t / 100, lyap=lyap)
    if run:
        return int(fn(p, s).steps_done)
    fn(p, s, 2)
    return int(pkg.solve.make_grid(p, s).n_steps)


def batched_call(pkg: Any, fn: Callable[..., Any], method: str, lyap: bool, t: float) -> int:
    """One batch of 64 points at tau = 10 with package pkg's simulate_batch: point-steps."""
    points = [pkg.params.Params(k=float(k), tau=10.0) for k in np.linspace(6.0, 16.0, 64)]
    s = pkg.solve.SolverSettings(method=method, t_end=t, window=t / 100, lyap=lyap)
    return sum(int(tr.steps_done) for tr in fn(points, s))


def interleaved(old_call: Callable[[], int], new_call: Callable[[], int],
                repeat: int) -> tuple[float, float, float]:
    """Median ns per step of each, and the median of the rounds' new / old ratios."""
    new_call(), old_call()  # compile or load
    ns: dict[str, list[float]] = {"old": [], "new": []}
    for r in range(repeat):
        pair = [("old", old_call), ("new", new_call)]
        for name, fn in (pair if r % 2 == 0 else pair[::-1]):
            t0 = time.process_time()
            steps = fn()
            ns[name].append((time.process_time() - t0) / steps * 1e9)
    ratio = statistics.median(b / a for a, b in zip(ns["old"], ns["new"], strict=True))
    return statistics.median(ns["old"]), statistics.median(ns["new"]), ratio


def against(tree: Path, repeat: int, spectra: bool) -> list[str]:
    """This tree's single kernels against DIR's, interleaved (see the docstring)."""
    from core.spectrum import spectrum

    old = other_core(tree)
    out = []
    for method, lyap in VARIANTS:  # the batched kernels, 64 lanes
        t = AGAINST_T[method] / 2
        a, b, ratio = interleaved(
            partial(batched_call, old, old.batch.simulate_batch, method, lyap, t),
            partial(batched_call, sys.modules["core"], simulate_batch, method, lyap, t), repeat)
        out.append(f"| {method}{' + λmax' if lyap else ''}, batched (64 lanes) | 6-16 | 10 | "
                   f"{a:.2f} | {b:.2f} | {ratio:.3f} |")
        print(out[-1], flush=True)
    cases = [(m, lyap, "run") for m in ("euler", "rk4", "stiff") for lyap in (False, True)]
    cases += [(m, False, "spectrum N = 2") for m in (("euler", "rk4") if spectra else ())]
    for method, lyap, what in cases:
        t = AGAINST_T[method] / (4 if what != "run" else 1)
        for k, tau in AGAINST_POINTS:
            run = what == "run"
            new_call = partial(one_call, sys.modules["core"], simulate if run else spectrum,
                               method, lyap, run, k, tau, t)
            old_call = partial(one_call, old, old.solve.simulate if run else old.spectrum.spectrum,
                               method, lyap, run, k, tau, t)
            a, b, ratio = interleaved(old_call, new_call, repeat)
            label = method + (" + λmax" if lyap else "") + ("" if what == "run" else f", {what}")
            out.append(f"| {label} | {k:g} | {tau:g} | {a:.2f} | {b:.2f} | {ratio:.3f} |")
            print(out[-1], flush=True)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--t-end", type=float, default=2000.0,
                    help="model time per Euler run (RK4 runs 10x longer at its 10x larger step)")
    ap.add_argument("--repeat", type=int, default=5, help="interleaved rounds (median)")
    ap.add_argument("--markdown", type=Path, help="also write the table to this file")
    ap.add_argument("--small-groups", type=Path, metavar="FILE",
                    help="also time groups of 2-5 points and write that table to FILE")
    ap.add_argument("--processes", type=int, default=1,
                    help="measure in this many fresh processes: the median, and the ratios' "
                         "ranges (default 1: this process)")
    ap.add_argument("--against", type=Path, metavar="DIR",
                    help="time the single kernels against DIR's core/ instead (see above)")
    ap.add_argument("--spectrum", action="store_true",
                    help="with --against: also the spectrum's tangent kernels")
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.against:
        print("| variant | k | tau | other, ns/step | this tree | this / other (median of rounds) |")
        print("|---|---:|---:|---:|---:|---:|")
        as_workers_run(partial(against, args.against, args.repeat, args.spectrum))
        return
    if args.child:  # one process of --processes: its figures as JSON on the last line
        print(json.dumps([(method + (" + λmax" if lyap else ""),
                           as_workers_run(partial(measure, method, lyap, args.t_end,
                                                  args.repeat)))
                          for method, lyap in VARIANTS]))
        return
    where = (f"median over {args.processes} processes (range of the ratios), each the median"
             if args.processes > 1 else "median")
    print(f"# {platform.processor() or platform.machine()}, {os.cpu_count()} cores, python "
          f"{platform.python_version()}; {len(POINTS)} points in {len(TAUS)} groups sharing "
          f"tau; {where} of {args.repeat} interleaved rounds, CPU time")
    if args.processes > 1:
        rows = in_processes(args.processes, args.t_end, args.repeat)
    else:
        rows = []
        for method, lyap in VARIANTS:
            name = method + (" + λmax" if lyap else "")
            rows.append((name, as_workers_run(partial(measure, method, lyap, args.t_end,
                                                      args.repeat))))
            print(table(rows)[-1], flush=True)
    lines = table(rows)
    print("\n".join(lines))
    if args.markdown:
        args.markdown.write_text("\n".join(lines) + "\n")
    if args.small_groups:
        small = as_workers_run(partial(small_groups, args.t_end))
        args.small_groups.write_text("\n".join(small) + "\n")


if __name__ == "__main__":
    main()
