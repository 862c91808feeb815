"""A worker's memory with long windows: the peak RSS of one batched Euler call against the
bytes core.solve.memory_of predicts for its runs, and the batch the default budget keeps.

    python benchmarks/bench_memory.py [--window 1e4] [--lanes 2 8 32 64] [--markdown FILE]

Each measurement runs in a fresh process (ru_maxrss is a process's peak), which first
compiles or loads the kernels and runs one lane, so that the baseline (interpreter,
numpy, numba, the kernels) is measured apart from what the lanes add.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

CHILD = """
import json, resource, sys
from core import Params, SolverSettings, run_batch
from core.solve import make_grid, memory_of
lanes, window = int(sys.argv[1]), float(sys.argv[2])
s = SolverSettings(method="euler", dt=1e-3, t_end=2 * window, window=window, lyap=True)
ps = [Params(k=6 + 0.25 * i) for i in range(lanes)]
run_batch(ps[:1], SolverSettings(method="euler", dt=1e-3, t_end=50, window=10, lyap=True))
base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
run_batch(ps, s)
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
predicted = sum(memory_of(make_grid(p, s), s).total for p in ps)
print(json.dumps({"base": base, "peak": peak, "predicted": predicted}))
"""


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--window", type=float, nargs="+", default=[1e4])
    parser.add_argument("--lanes", type=int, nargs="+", default=[2, 8, 32, 64],
                        help="batch sizes (a batch of 1 is the single kernel's run)")
    parser.add_argument("--markdown", type=Path, help="also write the table to this file")
    args = parser.parse_args()
    from slopetui.queue.batch_memory import MIB
    from slopetui.queue.defaults import MEMORY_MIB

    rows = ["| window | lanes | predicted | baseline RSS | peak RSS | added / predicted |",
            "|---:|---:|---:|---:|---:|---:|"]
    for window in args.window:
        print(f"window {window:g} (Euler, dt 1e-3, t_end 2 x window, with lambda_max)")
        print(f"{'lanes':>5} {'predicted MiB':>14} {'baseline MiB':>13} {'peak MiB':>9} "
              f"{'added MiB':>10} {'added / predicted':>18}")
        for lanes in args.lanes:
            out = subprocess.run([sys.executable, "-c", CHILD, str(lanes), str(window)],
                                 capture_output=True, text=True, check=True)
            m = json.loads(out.stdout.strip().splitlines()[-1])
            added = m["peak"] - m["base"]
            print(f"{lanes:>5} {m['predicted'] / MIB:>14.0f} {m['base'] / MIB:>13.0f} "
                  f"{m['peak'] / MIB:>9.0f} {added / MIB:>10.0f} "
                  f"{added / m['predicted']:>18.2f}", flush=True)
            rows.append(f"| {window:g} | {lanes} | {m['predicted'] / MIB:.0f} MiB | "
                        f"{m['base'] / MIB:.0f} MiB | {m['peak'] / MIB:.0f} MiB | "
                        f"{added / m['predicted']:.2f} |")
        per_run = m["predicted"] / args.lanes[-1]
        keep = max(1, int(MEMORY_MIB * MIB // per_run))
        print(f"default budget {MEMORY_MIB} MiB: a batch of these runs is cut to {keep} "
              f"(worker --memory MIB)")
    if args.markdown:
        args.markdown.write_text("\n".join(rows) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
