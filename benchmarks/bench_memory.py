"""A worker's memory with long windows: the peak RSS of one batched Euler call
(core.run_batch, as a worker calls it: integration, stiff re-integrations, analysis)
against the bytes core.solve.memory_of predicts for its runs and against what the memory
budget charges for them (slopetui.queue.batch_memory.charge), and the batch the default
budget keeps.

    python benchmarks/bench_memory.py [--window 1e4] [--lanes 2 8 32 64] [--k 6]
                                      [--params NAME=VALUE ...] [--markdown FILE]

The lanes are k = K, K + 0.25, ... (the paper's other values, or --params): with the
defaults, from k = 7.25 on some lanes drive Euler's s_y below 0 at window 1e5 and are
integrated again by the stiff scheme (core.point), which the column "stiff" counts; with
--k 6.25 --params b=9 tau=0.2 most lanes are, at any window. Each measurement runs in a fresh
process (ru_maxrss is a process's peak), which first compiles or loads the kernels (the
single and batched Euler kernels and the stiff kernel) on short runs, so that the baseline
(interpreter, numpy, numba, the kernels) is measured apart from what the lanes add.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

#: Short runs through every kernel a batch may call: the single and batched Euler kernels
#: and the stiff one (a lane's re-integration).
WARM_UP = """
from core.params import Params
from core.point import run_batch
from core.solve import SolverSettings
from core.batch import MIN_LANES
short = dict(dt=1e-3, t_end=50, window=10, lyap=True)
for method, n in (("euler", 1), ("euler", MIN_LANES), ("stiff", 1)):
    run_batch([Params()] * n, SolverSettings(method=method, **short))
"""
CHILD = WARM_UP + """
import json, resource, sys
from core.solve import make_grid, memory_of
lanes, window, k = int(sys.argv[1]), float(sys.argv[2]), float(sys.argv[3])
fixed = json.loads(sys.argv[4])
s = SolverSettings(method="euler", dt=1e-3, t_end=2 * window, window=window, lyap=True)
ps = [Params(**fixed, k=k + 0.25 * i) for i in range(lanes)]
base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
results = run_batch(ps, s)
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
sizes = [memory_of(make_grid(p, s), s).total for p in ps]
stiff = sum("stiff-fallback" in r.summary.flags for r in results)
print(json.dumps({"base": base, "peak": peak, "sizes": sizes, "stiff": stiff}))
"""


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--window", type=float, nargs="+", default=[1e4])
    parser.add_argument("--lanes", type=int, nargs="+", default=[2, 8, 32, 64],
                        help="batch sizes (under core.batch.MIN_LANES, the single kernel's runs)")
    parser.add_argument("--k", type=float, default=6.0, help="the first lane's k")
    parser.add_argument("--params", nargs="*", default=[], metavar="NAME=VALUE",
                        help="other parameters of every lane (default: the paper's)")
    parser.add_argument("--markdown", type=Path, help="also write the table to this file")
    args = parser.parse_args()
    fixed = {name: float(value) for name, value in (a.split("=", 1) for a in args.params)}
    from slopetui.queue.batch_memory import MIB, charge, fitting_sizes
    from slopetui.queue.defaults import MEMORY_MIB

    # compiled here, once, into numba's cache (core.jit_cache), so that the measured
    # processes load the kernels: one that compiles them holds ~100 MiB more from then on
    # (a baseline of 259 MiB against 159, for the same added RSS: 1639 MiB against 1641
    # for 16 lanes at window 1e5), and the baselines of the rows would differ
    subprocess.run([sys.executable, "-c", WARM_UP], check=True)
    rows = ["| window | lanes | stiff | predicted | baseline RSS | peak RSS | added / predicted "
            "| added / charged |",
            "|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for window in args.window:
        print(f"window {window:g} (Euler, dt 1e-3, t_end 2 x window, with lambda_max)")
        print(f"{'lanes':>5} {'stiff':>5} {'predicted MiB':>14} {'baseline MiB':>13} "
              f"{'peak MiB':>9} {'added MiB':>10} {'added / predicted':>18} {'added / charged':>16}")
        for lanes in args.lanes:
            out = subprocess.run([sys.executable, "-c", CHILD, str(lanes), str(window), str(args.k),
                                  json.dumps(fixed)],
                                 capture_output=True, text=True, check=True)
            m = json.loads(out.stdout.strip().splitlines()[-1])
            added, predicted, charged = m["peak"] - m["base"], sum(m["sizes"]), charge(m["sizes"])
            print(f"{lanes:>5} {m['stiff']:>5} {predicted / MIB:>14.0f} {m['base'] / MIB:>13.0f} "
                  f"{m['peak'] / MIB:>9.0f} {added / MIB:>10.0f} {added / predicted:>18.2f} "
                  f"{added / charged:>16.2f}", flush=True)
            rows.append(f"| {window:g} | {lanes} | {m['stiff']} | {predicted / MIB:.0f} MiB | "
                        f"{m['base'] / MIB:.0f} MiB | {m['peak'] / MIB:.0f} MiB | "
                        f"{added / predicted:.2f} | {added / charged:.2f} |")
        keep = fitting_sizes(m["sizes"][:1] * 64, MEMORY_MIB * MIB)
        print(f"default budget {MEMORY_MIB} MiB: a batch of 64 such runs is cut to {keep} "
              f"(worker --memory MIB)")
    if args.markdown:
        args.markdown.write_text("\n".join(rows) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
