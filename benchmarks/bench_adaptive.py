"""Adaptive phase diagrams against brute force: how many runs they save, and how often
their diagram (computed and inferred runs) agrees with the brute-force one.

Run:  python benchmarks/bench_adaptive.py [--num 128] [--levels 3] [--planes k-tau,c-tau]
          [--method rk4] [--dt 0.01] [--t-end 2000] [--window 500] [--lyap] [--workers N]
          [--stop t_end|certified]
          [--adaptive-only]

For each plane, the same final lattice (num x num) twice, each in its own temporary
SQLite store (one store would let the adaptive sweep copy every point from the brute
force sweep's cache): once brute force, every point computed, once adaptive, level by
level (``slopetui.sweeps.adaptive.advance`` after each level, as idle workers do).
Prints per plane: runs computed by each, their ratio, the share of lattice points where
the adaptive label (computed or inferred) equals the brute-force label, which labels
differ, and the wall times. Target: >= 99% agreement with >= 5x fewer runs. The
saving grows with the lattice (the refined bands grow with its side, the lattice with its
square): (k, tau) meets it at 128 x 128 (the default), (c, tau), whose complex strip is two
boundaries close together, at 256 x 256 (--num 256 --levels 4); neither at 64 x 64 (~3x).

Two checks that need no further computation: the model is deterministic, so the
adaptive sweep's computed points carry the brute-force labels, and replaying the pure
geometry (``refine_in_memory``) on the brute-force labels must give the store's result
exactly; the same replay at other ``levels`` shows what they would have cost and missed.

``--adaptive-only`` computes the adaptive sweep alone (runs per level, wall time): a lattice
whose brute force would take too long, checked against brute force on a smaller one (the
end-to-end diagram: 100 x 100 at the paper's settings, Euler dt 1e-3 to t = 1e5, with
lambda_max; docs/speed.md).

Runs are computed in this process (one core) unless ``--workers N``, which starts
``slopetui worker -j N --exit-when-idle`` for each level. ``--keep DIR`` keeps the
stores (``<plane>-brute.db``, ``<plane>-adaptive.db``) for ``slopetui show`` or SQL; it
refuses a folder that already holds them (their cache would serve the new sweeps).
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

from sqlalchemy import select

from core.point import run_point
from slopetui.queue import jobs
from slopetui.store.database import Database
from slopetui.store.models import Run, Sweep
from slopetui.store.open import open_store
from slopetui.sweeps.adaptive import advance
from slopetui.sweeps.refinement import FAILED, refine_in_memory
from slopetui.sweeps.spec import parse_spec
from slopetui.sweeps.submit import submit

#: Planes from the paper (README, slopetui/sweeps/presets.py), far from the fixed point
#: (delta = 0.1): each has a sliding/oscillating boundary on the Hopf line and a complex
#: region beyond it.
PLANES: dict[str, dict[str, object]] = {
    "k-tau": {"x": {"param": "k", "start": 2, "stop": 20},
              "y": {"param": "tau", "start": 0.5, "stop": 10}, "fixed": {"delta": 0.1}},
    # the certified stop's targets' plane (docs/speed.md)
    "k-tau-wide": {"x": {"param": "k", "start": 0.5, "stop": 25},
                   "y": {"param": "tau", "start": 0.5, "stop": 20}, "fixed": {"delta": 0.1}},
    "c-tau": {"x": {"param": "c", "start": 0.1, "stop": 10},
              "y": {"param": "tau", "start": 0.1, "stop": 20}, "fixed": {"k": 12, "delta": 0.1}},
    "a-tau": {"x": {"param": "a", "start": 0.1, "stop": 10},
              "y": {"param": "tau", "start": 0.1, "stop": 20}, "fixed": {"k": 12, "delta": 0.1}},
    "b-tau": {"x": {"param": "b", "start": 0.5, "stop": 24},
              "y": {"param": "tau", "start": 0.1, "stop": 20}, "fixed": {"k": 12, "delta": 0.1}},
}

Labels = dict[tuple[int, int], str]


def spec_data(plane: str, args: argparse.Namespace, adaptive: bool) -> dict[str, object]:
    p = PLANES[plane]
    data: dict[str, object] = {
        "name": f"{plane} {'adaptive' if adaptive else 'brute force'}",
        "x": {**p["x"], "num": args.num}, "y": {**p["y"], "num": args.num},  # type: ignore[dict-item]
        "fixed": p["fixed"],
        "solver": {"method": args.method, "dt": args.dt, "t_end": args.t_end,
                   "window": args.window, "lyap": args.lyap, "stop": args.stop}}
    if adaptive:
        data["adaptive"] = {"levels": args.levels}
    return data


def compute_queued(db: Database, path: Path, workers: int) -> int:
    """Compute every queued run: in this process, or with a worker pool."""
    if workers:
        subprocess.run([sys.executable, "-m", "slopetui", "worker", "-j", str(workers),
                        "--exit-when-idle", "--db", f"sqlite:///{path}",
                        "--log", str(path.with_suffix(".log"))],
                       check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        return 0
    n = 0
    while batch := jobs.claim_batch(db, "bench", 1):
        for job in jobs.begin(db, batch, "bench"):
            jobs.complete(db, job, "bench", run_point(job.params, job.settings).as_record())
            n += 1
    return n


def labels_of(db: Database, sweep_id: int) -> tuple[Labels, Labels]:
    """(every point's label, the labels of computed points) of a finished sweep."""
    with db.sessions() as s:
        rows = s.execute(select(Run.ix, Run.iy, Run.status, Run.regime, Run.inferred)
                         .where(Run.sweep_id == sweep_id)).all()
    every: Labels = {}
    computed: Labels = {}
    for ix, iy, status, regime, inferred in rows:
        every[ix, iy] = regime if status == "done" else FAILED
        if not inferred:
            computed[ix, iy] = every[ix, iy]
    return every, computed


def fresh_store(path: Path) -> Database:
    if path.exists():
        raise SystemExit(f"--keep: {path} exists; its cache would serve the new sweep")
    return open_store(f"sqlite:///{path}")


def brute_force(folder: Path, plane: str, args: argparse.Namespace) -> tuple[Labels, float]:
    path = folder / f"{plane}-brute.db"
    db = fresh_store(path)
    t0 = time.perf_counter()
    sweep = submit(db, parse_spec(spec_data(plane, args, adaptive=False)))
    compute_queued(db, path, args.workers)
    elapsed = time.perf_counter() - t0
    labels, _ = labels_of(db, sweep.sweep_id)
    return labels, elapsed


def adaptive(folder: Path, plane: str, args: argparse.Namespace
             ) -> tuple[Labels, Labels, float, list[int]]:
    path = folder / f"{plane}-adaptive.db"
    db = fresh_store(path)
    t0 = time.perf_counter()
    sweep = submit(db, parse_spec(spec_data(plane, args, adaptive=True)))
    while True:  # workers advance the levels themselves; in-process, this loop does
        compute_queued(db, path, args.workers)
        advance(db, sweep.sweep_id)
        with db.sessions() as s:
            if s.get(Sweep, sweep.sweep_id).refined:
                break
    elapsed = time.perf_counter() - t0
    every, computed = labels_of(db, sweep.sweep_id)
    with db.sessions() as s:
        levels = Counter(s.scalars(select(Run.level).where(Run.sweep_id == sweep.sweep_id,
                                                          Run.inferred.is_(False))))
    return every, computed, elapsed, [levels[lv] for lv in sorted(levels)]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--num", type=int, default=128, help="points per axis (default 128)")
    ap.add_argument("--levels", type=int, default=3, help="adaptive levels (default 3)")
    ap.add_argument("--planes", default="k-tau,c-tau",
                    help=f"comma-separated, of {', '.join(PLANES)} (default k-tau,c-tau)")
    ap.add_argument("--method", default="rk4")
    ap.add_argument("--dt", type=float, default=0.01)
    ap.add_argument("--t-end", dest="t_end", type=float, default=2000.0)
    ap.add_argument("--window", type=float, default=500.0)
    ap.add_argument("--lyap", action="store_true", help="compute lambda_max (off by default)")
    ap.add_argument("--stop", choices=("t_end", "certified"), default="t_end",
                    help="the runs' stop rule (default t_end: the paper's protocol)")
    ap.add_argument("--workers", type=int, default=0,
                    help="compute with `slopetui worker -j N` (default: in this process)")
    ap.add_argument("--adaptive-only", action="store_true",
                    help="compute the adaptive sweep only (no brute force to compare with)")
    ap.add_argument("--markdown", type=Path, metavar="FILE",
                    help="also add a row per plane to the Markdown table in FILE (made with "
                         "its header if missing)")
    ap.add_argument("--keep", metavar="DIR",
                    help="keep the stores in DIR (default: a temporary folder, deleted)")
    args = ap.parse_args()
    planes = args.planes.split(",")
    for plane in planes:
        if plane not in PLANES:
            ap.error(f"--planes: unknown plane {plane!r}; one of {', '.join(PLANES)}")
    n = args.num
    print(f"lattice {n} x {n} = {n * n} points, levels {args.levels}; {args.method} dt "
          f"{args.dt:g} to t = {args.t_end:g}, window {args.window:g}, lambda_max "
          f"{'on' if args.lyap else 'off'}, stop {args.stop}; {args.workers or 'in-process'} worker(s)")
    if args.keep:
        Path(args.keep).mkdir(parents=True, exist_ok=True)
        for plane in planes:
            report(Path(args.keep), plane, args)
        return
    with tempfile.TemporaryDirectory(prefix="bench-adaptive-") as tmp:
        for plane in planes:
            report(Path(tmp), plane, args)


def add_row(args: argparse.Namespace, row: str) -> None:
    """Append a row to --markdown's table (with its header, and the settings, if new)."""
    if args.markdown is None:
        return
    if not args.markdown.exists():
        args.markdown.write_text(
            f"| lattice ({args.method} dt {args.dt:g} to t = {args.t_end:g}, window "
            f"{args.window:g}, λmax {'on' if args.lyap else 'off'}, stop {args.stop}, {args.workers or 1} "
            f"worker(s)) | runs computed | wall time | points agreeing with brute force |\n"
            "|---|---:|---:|---:|\n")
    with args.markdown.open("a") as f:
        f.write(row + "\n")


def report(folder: Path, plane: str, args: argparse.Namespace) -> None:
    n = args.num
    if args.adaptive_only:
        every, computed, t_adaptive, per_level = adaptive(folder, plane, args)
        print(f"\n{plane}: {n} x {n}, regimes {dict(Counter(every.values()))}")
        print(f"  runs computed   adaptive {len(computed)} of {n * n} (per level {per_level}), "
              f"{n * n / len(computed):.2f}x fewer than brute force")
        print(f"  wall time       adaptive {t_adaptive:.1f} s ({t_adaptive / 60:.1f} min)")
        add_row(args, f"| {plane} {n} × {n}, adaptive only | {len(computed)} of {n * n} "
                      f"({n * n / len(computed):.2f}× fewer) | **{t_adaptive / 60:.1f} min** | "
                      f"(no brute force) |")
        return
    brute, t_brute = brute_force(folder, plane, args)
    every, computed, t_adaptive, per_level = adaptive(folder, plane, args)
    same = sum(every[p] == brute[p] for p in brute)
    wrong = Counter(f"{brute[p]}->{every[p]}" for p in brute if every[p] != brute[p])
    print(f"\n{plane}: {n} x {n}, regimes {dict(Counter(brute.values()))}")
    print(f"  runs computed   brute force {len(brute)}, adaptive {len(computed)} "
          f"(per level {per_level}), {len(brute) / len(computed):.2f}x fewer")
    print(f"  agreement       {100 * same / len(brute):.2f}% of points "
          f"({len(brute) - same} differ"
          f"{': ' + ', '.join(f'{k} {v}' for k, v in wrong.most_common()) if wrong else ''})")
    print(f"  wall time       brute force {t_brute:.1f} s, adaptive {t_adaptive:.1f} s")
    add_row(args, f"| {plane} {n} × {n}, brute force | {len(brute)} | {t_brute / 60:.1f} min "
                  f"| (reference) |")
    add_row(args, f"| {plane} {n} × {n}, adaptive | {len(computed)} ({len(brute) / len(computed):.2f}"
                  f"× fewer) | {t_adaptive / 60:.1f} min | **{100 * same / len(brute):.2f}%** |")
    # determinism: the store's adaptive sweep is the pure geometry run on brute force labels
    replay = refine_in_memory(n, n, args.levels, lambda ix, iy: brute[ix, iy])
    exact = set(replay.computed) == set(computed) and replay.labels == every
    print(f"  store = geometry replayed on the brute-force labels: {'yes' if exact else 'NO'}")
    for levels in range(1, 7):
        if 2 ** levels >= n or levels == args.levels:
            continue
        r = refine_in_memory(n, n, levels, lambda ix, iy: brute[ix, iy])
        agree = sum(r.labels[p] == brute[p] for p in brute)
        print(f"  replay at levels {levels}: {len(r.computed)} computed "
              f"({len(brute) / len(r.computed):.2f}x fewer), {100 * agree / len(brute):.2f}% agree")


if __name__ == "__main__":
    main()
