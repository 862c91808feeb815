"""Start-up of the commands that compute nothing: the wall and CPU
time of `slopetui --help`, `status`, `runs` and `sql "select 1"`, and whether each loaded
numba (or numpy); and of `slopetui show` of a 100 x 100 sweep at 120 x 40, on a quiet
machine (benchmarks/bench_tui.py times it with two workers busy, the issue's condition).

    .venv/bin/python benchmarks/bench_startup.py [--repeat 15] [--sweeps 3]

Each command runs as a user types it (the `slopetui` script beside this interpreter), in a
fresh process, against a small SQLite store made in a temporary folder (a few queued
sweeps of 5 runs; a store at the current schema, so no migration runs); `show`, against
a store of its own: bench_tui.py's 100 x 100 (k, tau) sweep, 9,000 of its runs given
results (``--no-show`` leaves it out, and the ~10 s it takes to make). The commands take
turns (one round of every command, then the next round), so that a change in the
machine's load touches them all alike; the table gives the median and the best of the
rounds. Wall time is time.perf_counter around the process; CPU time (user + system) is
resource.getrusage(RUSAGE_CHILDREN) before and after it. Whether numba and numpy were
loaded is asked of a separate run of the same command in a probe process (sys.modules
after slopetui.cli.main returned), so that the probe costs the timings nothing.

Python bytecode is cached in a temporary PYTHONPYCACHEPREFIX and the first round is
thrown away, as on an installed copy that has run once; $PYTHONDONTWRITEBYTECODE, if set,
is ignored for the children (without bytecode, every module of slopetui and core is
compiled at each start, ~0.1-0.2 s more). --no-bytecode-cache keeps the environment as it is.

Targets: `--help` <= 0.5 s and `status` <= 1 s of wall time on an idle machine;
`runs` and `sql` are held to status's second, `show` to its own (the issue's 1 s, there
with two workers busy). The load average is printed before and
after: on a busy machine the figures say little.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

#: The commands, and their wall-time target in seconds (runs and sql: status's).
COMMANDS: list[tuple[str, list[str], float]] = [
    ("--help", ["--help"], 0.5),
    ("status", ["status"], 1.0),
    ("runs", ["runs"], 1.0),
    ("sql", ["sql", "select 1"], 1.0),
]
#: `show`, on the store of the 100 x 100 sweep (``SHOW_DB``), and its target.
SHOW: tuple[str, list[str], float] = ("show", ["show", "1", "--width", "120", "--height", "40"],
                                      1.0)

#: What a probe process prints after the command ran: which heavy modules it loaded.
PROBE = """
import contextlib, io, json, sys
from slopetui.cli import main
with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
    try:
        main(sys.argv[1:])
    except SystemExit:
        pass
print(json.dumps({m: m in sys.modules for m in ("numba", "numpy", "sqlalchemy")}))
"""


def slopetui_command() -> list[str]:
    """The `slopetui` script beside this interpreter (as installed), else `python -m slopetui`."""
    script = Path(sys.executable).with_name("slopetui")
    return [str(script)] if script.exists() else [sys.executable, "-m", "slopetui"]


def make_store(folder: Path, n_sweeps: int) -> str:
    """A SQLite store at the current schema with ``n_sweeps`` queued sweeps of 5 runs."""
    from slopetui.store.open import open_store
    from slopetui.sweeps.spec import parse_spec
    from slopetui.sweeps.submit import submit

    url = f"sqlite:///{folder / 'store.db'}"
    db = open_store(url)
    for i in range(n_sweeps):
        submit(db, parse_spec({"name": f"bench {i}",
                               "x": {"param": "k", "start": 4, "stop": 12, "num": 5},
                               "fixed": {"tau": 2.0 + i},
                               "solver": {"method": "rk4", "dt": 0.01, "t_end": 200.0,
                                          "window": 100.0}}))
    db.dispose()
    return url


def make_plane_store(folder: Path) -> str:
    """A SQLite store with bench_tui.py's 100 x 100 sweep (id 1), 1,000 of its runs queued."""
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    from bench_tui import build_store

    url = f"sqlite:///{folder / 'plane.db'}"
    build_store(url, queued=1000)
    return url


def timed(cmd: list[str], env: dict[str, str]) -> tuple[float, float]:
    """Wall and CPU seconds (user + system) of one run of ``cmd``."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    out = subprocess.run(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                         text=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if out.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed ({out.returncode}): {out.stderr.strip()}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def loaded(argv: list[str], env: dict[str, str]) -> dict[str, bool]:
    out = subprocess.run([sys.executable, "-c", PROBE, *argv], env=env, capture_output=True,
                         text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=15, help="rounds timed (default 15)")
    parser.add_argument("--sweeps", type=int, default=3,
                        help="queued sweeps of 5 runs in the store (default 3)")
    parser.add_argument("--no-bytecode-cache", dest="bytecode", action="store_false",
                        help="leave $PYTHONDONTWRITEBYTECODE and $PYTHONPYCACHEPREFIX as they are")
    parser.add_argument("--no-show", dest="show", action="store_false",
                        help="leave out `show` of the 100 x 100 sweep (and making its store)")
    parser.add_argument("--markdown", type=Path, help="also write the table to this file")
    args = parser.parse_args()
    commands = [*COMMANDS, SHOW] if args.show else COMMANDS

    with tempfile.TemporaryDirectory(prefix="bench_startup.") as tmp:
        folder = Path(tmp)
        env = {**os.environ, "SLOPETUI_DB": make_store(folder, args.sweeps),
               "NO_COLOR": "1", "COLUMNS": "120"}
        if args.bytecode:
            env.pop("PYTHONDONTWRITEBYTECODE", None)
            env["PYTHONPYCACHEPREFIX"] = str(folder / "pycache")
        if args.show:
            name, argv, target = SHOW
            commands[-1] = (name, [*argv, "--db", make_plane_store(folder)], target)
        base = slopetui_command()
        print(f"{' '.join(base)}, SQLite store with {args.sweeps} queued sweeps"
              f"{' (show: a 100 x 100 sweep)' if args.show else ''}; "
              f"bytecode {'cached' if args.bytecode else 'as the environment has it'}; "
              f"load average {os.getloadavg()[0]:.2f} before", flush=True)

        for _, argv, _ in commands:  # round 0, thrown away: bytecode, the page cache
            timed([*base, *argv], env)
        walls: dict[str, list[float]] = {name: [] for name, _, _ in commands}
        cpus: dict[str, list[float]] = {name: [] for name, _, _ in commands}
        for _ in range(args.repeat):
            for name, argv, _ in commands:
                wall, cpu = timed([*base, *argv], env)
                walls[name].append(wall)
                cpus[name].append(cpu)
        probes = {name: loaded(argv, env) for name, argv, _ in commands}
        load_after = os.getloadavg()[0]

    print(f"\n{'command':10} {'target':>7} {'wall median':>12} {'wall best':>10} "
          f"{'CPU median':>11} {'CPU best':>9}  {'numba':6} {'numpy':6} verdict")
    failed = False
    rows = ["| command (SQLite store, bytecode cached) | wall, median (best) | CPU, median | "
            "target | numba loaded |",
            "|---|---:|---:|---|---|"]
    for name, _, target in commands:
        med = statistics.median(walls[name])
        ok = med <= target and not probes[name]["numba"]
        failed |= not ok
        print(f"{name:10} {target:>6.1f}s {med:>11.3f}s {min(walls[name]):>9.3f}s "
              f"{statistics.median(cpus[name]):>10.3f}s {min(cpus[name]):>8.3f}s  "
              f"{'yes' if probes[name]['numba'] else 'no':6} "
              f"{'yes' if probes[name]['numpy'] else 'no':6} "
              f"{'ok' if ok else 'MISSED'}")
        what = f"`slopetui {name}`" + (" (100 × 100 sweep, 120 × 40)" if name == "show" else "")
        rows.append(f"| {what} | **{med:.2f} s** ({min(walls[name]):.2f} s) | "
                    f"{statistics.median(cpus[name]):.2f} s | ≤ {target:g} s: "
                    f"{'met' if ok else '**not met**'} | "
                    f"{'yes' if probes[name]['numba'] else 'no'} |")
    print(f"\n{args.repeat} rounds, commands interleaved; load average {load_after:.2f} after. "
          "verdict: median wall within the target and numba not loaded.")
    if args.markdown:
        args.markdown.write_text("\n".join(rows) + "\n")
    return 1 if failed else 0


if __name__ == "__main__":
    with contextlib.suppress(KeyboardInterrupt):
        sys.exit(main())
