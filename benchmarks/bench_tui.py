"""The application at scale: a 100 x 100 sweep open at 120 x 40 while both
workers compute, measured from outside, as a user meets it.

    python benchmarks/bench_tui.py [--switches 40] [--idle 20] [--shows 5] [--queued 1000]

A new SQLite store in a temporary folder gets one (k, tau) sweep of 100 x 100 runs at the
paper's settings (Euler, dt 1e-3, t_end 1e5, with lambda_max). All but ``--queued`` of
its runs are given plausible results through the queue's own calls (claim, begin,
complete; the regime from the exact Hopf curve, a band of complex runs along it),
so that 10,000 runs need not be computed. A small 5 x 5 plane submitted before it, every
run given a result, is the sweeps table's second row (newest first). A worker pool
(``slopetui worker``, one worker per core, batches of 8) then computes the rest, so the
diagram fills while it is measured and both cores are busy. Once the pool has finished
its first runs (its kernels are compiled), the application (``slopetui --no-workers``)
starts in tmux at 120 x 40 and the script measures:

- screen switches: a key (2 queue, 4 branches, 1 sweeps), then ``tmux capture-pane``
  polled until the new screen's own text is on screen; half the switches go back to the
  sweeps screen and its 10,000-run diagram. Between two switches a pause of 0.3 to 1.3 s
  (a fixed sequence), so that they fall at every phase of the 2 s refresh. The first
  visit of the queue and branches screens builds them (Textual composes a mode's screen
  when first shown): those two are timed apart, before the switches.
- the idle application's CPU: utime + stime of its process (/proc/PID/stat, every thread)
  over ``--idle`` seconds with the sweeps screen in view, the 100 x 100 sweep (the
  table's first row) selected, then the small one (its second row), then with the queue
  screen in view (the sweeps screen hidden under it), as a share of one core. Both rows:
  a screen that spun only with a row other than the first selected (every refill of
  the table selected and loaded the first sweep, then the selected one again) took a
  whole core idle, where the first row alone showed 3%.
- ``slopetui show SWEEP --width 120 --height 40``: wall time of the whole command, a fresh
  process each time (best and median of ``--shows``), and its CPU time.

The latencies include tmux's own (a capture every ~5 ms, a few ms each): they are an
upper bound of the application's. The CPU time the application used is printed too,
during each switch (/proc, 10 ms ticks) and per switch all told (its refreshes between
switches included): unlike wall time, it hardly depends on what else the machine runs.
So is the load average before and after, which says what else did.

Python bytecode is cached in a temporary PYTHONPYCACHEPREFIX for every process the
script starts ($PYTHONDONTWRITEBYTECODE, if set, is ignored for them), and the first
``show`` is not counted, as on an installed copy that has run once (as
bench_startup.py); --no-bytecode-cache keeps the environment as it is. Run it against
another checkout of the code with ``PYTHONPATH=/path/to/checkout python
benchmarks/bench_tui.py`` from outside that checkout: every process the script starts
inherits the environment. Needs tmux.
"""

from __future__ import annotations

import argparse
import math
import os
import re
import resource
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

SIZE = (120, 40)
SOCKET = "slopetui-bench-tui"
SESSION = "bench"
#: Text that only the screen in view shows once it has its data: the sweeps screen's
#: cursor line under the diagram, the queue's workers table, the branches' table head.
MARKERS = {"1": "enter opens it", "2": "jobs done", "4": "criticality"}
#: The switches, in order: each screen, and back to the sweeps screen.
CYCLE = ("2", "1", "4", "1")
#: Seconds to wait for a screen before calling the switch lost.
SWITCH_TIMEOUT = 30.0
SPEC = {"name": "100 x 100 (k, tau) plane",
        "x": {"param": "k", "start": 2, "stop": 20, "num": 100},
        "y": {"param": "tau", "start": 0.5, "stop": 10, "num": 100},
        "fixed": {"delta": 0.1},
        "solver": {"method": "euler", "dt": 1e-3, "t_end": 1e5, "window": 1e4}}
#: The sweeps table's second row: small, every run given a result, at another delta so
#: that none of its points is one of SPEC's (submit would take its result for SPEC's run).
SECOND_SPEC = {"name": "second row: 5 x 5 (k, tau) plane",
               "x": {"param": "k", "start": 2, "stop": 20, "num": 5},
               "y": {"param": "tau", "start": 0.5, "stop": 10, "num": 5},
               "fixed": {"delta": 0.2}, "solver": SPEC["solver"]}
#: The cursor line under a phase diagram names the run under the cursor.
CURSOR_RUN = re.compile(r"\(run (\d+); enter opens it\)")


def slopetui_cmd(*args: str) -> list[str]:
    return [sys.executable, "-m", "slopetui", *args]


# -- the store --

def synthetic_record(k: float, tau: float, k_hopf: float) -> dict[str, object]:
    """A plausible result at (k, tau): sliding on the stable side of the exact Hopf curve,
    oscillatory beyond it, complex in a band just beyond it (where the paper's complex
    runs sit), with values of the right kind in every result field."""
    beyond = k - k_hopf
    if beyond < 0:
        regime, attractor, peaks, lam = "sliding", "fixed-point", [], -0.05
    elif beyond < 0.4 and (round(k * 7) + round(tau * 5)) % 3 == 0:
        regime, attractor, peaks, lam = "complex", "chaotic", [1.9, 2.2, 2.6], 0.01
    else:
        regime, attractor, peaks, lam = "oscillatory", "periodic", [2.2], 0.0
    return {"regime": regime, "detail": "synthetic", "lambda_max": lam, "lambda_err": 1e-3,
            "amplitude": 0.0 if not peaks else 3.0, "period": math.nan if not peaks else 10.5,
            "period_count": 0 if not peaks else 1, "maxima_per_period": len(peaks),
            "attractor": attractor, "settled": True, "flags": "", "peaks": peaks,
            "frequency": math.nan if not peaks else 0.095, "drift": 0.02,
            "zero_one_k": math.nan, "t_blowup": None, "runtime_s": 0.8,
            "certified": False, "certificate": "not attempted", "multipliers": [], "slips": 0,
            "dt_error": math.nan, "spectrum": [], "spectrum_err": [], "t_stop": 100.0}


def submit_filled(db, spec_dict: Mapping[str, Any], queued: int) -> tuple[int, int]:
    """Submit a sweep and give all but ``queued`` of its runs their results (no other
    sweep may have queued runs); returns the sweep's id and its last run's id."""
    import numpy as np
    from sqlalchemy import func, select

    from slopetui.queue import jobs
    from slopetui.store.models import Run
    from slopetui.sweeps.diagram import plane_hopf
    from slopetui.sweeps.spec import parse_spec
    from slopetui.sweeps.submit import submit

    spec = parse_spec(spec_dict)
    sweep = submit(db, spec).sweep_id
    curve = plane_hopf(spec)
    assert curve is not None and len(curve[0])
    order = np.argsort(curve[1])
    hopf_k, hopf_tau = curve[0][order], curve[1][order]
    to_fill = spec.n_runs - queued
    filled = 0
    while filled < to_fill:
        batch = jobs.claim_batch(db, "bench-fill", min(500, to_fill - filled))
        if not batch:
            break
        for job in jobs.begin(db, batch, "bench-fill"):
            k_hopf = float(np.interp(job.params.tau, hopf_tau, hopf_k))
            jobs.complete(db, job, "bench-fill", synthetic_record(job.params.k, job.params.tau,
                                                                   k_hopf))
            filled += 1
    with db.sessions() as s:
        last = s.execute(select(func.max(Run.id)).where(Run.sweep_id == sweep)).scalar_one()
    return sweep, last


def build_store(url: str, queued: int) -> tuple[int, int]:
    """The small sweep (SECOND_SPEC, every run given a result), then the 100 x 100 one,
    all but ``queued`` of its runs given results: the big sweep's id, and the last run
    id of the small one."""
    from slopetui.store.open import open_store

    db = open_store(url)
    try:
        _, second_last = submit_filled(db, SECOND_SPEC, 0)
        sweep, _ = submit_filled(db, SPEC, queued)
    finally:
        db.dispose()
    return sweep, second_last


def done_count(url: str, sweep: int) -> int:
    from slopetui.store.open import open_store
    from slopetui.sweeps.progress import sweep_progress

    db = open_store(url)
    try:
        return sum(p.done for p in sweep_progress(db, [sweep]))
    finally:
        db.dispose()


# -- tmux --

def tmux(*args: str) -> str:
    return subprocess.run(["tmux", "-L", SOCKET, *args], check=True, capture_output=True,
                          text=True).stdout


def screen_text() -> str:
    return tmux("capture-pane", "-p", "-t", SESSION)


def wait_until_shown(shown: Callable[[str], bool], what: str,
                     timeout: float = SWITCH_TIMEOUT) -> float:
    """Seconds until ``shown(screen text)`` holds (polling tmux); raises on timeout."""
    start = time.perf_counter()
    while not shown(screen_text()):
        if time.perf_counter() - start > timeout:
            raise RuntimeError(f"{what} did not appear within {timeout} s:\n{screen_text()}")
        time.sleep(0.005)
    return time.perf_counter() - start


def wait_for(marker: str, timeout: float = SWITCH_TIMEOUT) -> float:
    """Seconds until ``marker`` is on screen (polling tmux); raises on timeout."""
    return wait_until_shown(lambda text: marker in text, repr(marker), timeout)


def cursor_run(text: str) -> int | None:
    """The run under the phase diagram's cursor, as the cursor line names it."""
    found = CURSOR_RUN.search(text)
    return int(found.group(1)) if found else None


def cpu_seconds(pid: int) -> float:
    """utime + stime of the process, every thread (s)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def idle_share(pid: int, seconds: float) -> float:
    """The process's CPU over ``seconds`` of wall time, as a share of one core."""
    before, start = cpu_seconds(pid), time.perf_counter()
    time.sleep(seconds)
    return (cpu_seconds(pid) - before) / (time.perf_counter() - start)


# -- the measurements --

def switch(key: str, pid: int) -> tuple[float, float]:
    """Seconds from the key to its screen's text on screen, and the CPU seconds the
    application (``pid``) used meanwhile."""
    cpu = cpu_seconds(pid)
    tmux("send-keys", "-t", SESSION, key)
    start = time.perf_counter()
    wait_for(MARKERS[key])
    return time.perf_counter() - start, cpu_seconds(pid) - cpu


def switches(n: int, pid: int) -> tuple[dict[str, list[float]], list[float]]:
    """n switches along CYCLE: latencies (s) by the screen switched to, and the CPU (s)
    the application used during each."""
    out: dict[str, list[float]] = {key: [] for key in MARKERS}
    cpu = []
    for i in range(n):
        key = CYCLE[i % len(CYCLE)]
        time.sleep(0.3 + (i * 0.37) % 1.0)  # a fixed spread over the refresh period
        wall, used = switch(key, pid)
        out[key].append(wall)
        cpu.append(used)
    return out, cpu


def show_times(env: dict[str, str], sweep: int, n: int) -> tuple[list[float], list[float]]:
    """Wall and CPU times (user + system) of ``slopetui show``, after one run not counted
    (bytecode, disk cache)."""
    times, cpu = [], []
    for i in range(n + 1):
        used = resource.getrusage(resource.RUSAGE_CHILDREN)
        start = time.perf_counter()
        subprocess.run(slopetui_cmd("show", str(sweep), "--width", str(SIZE[0]), "--height",
                                    str(SIZE[1])), env=env, check=True,
                       stdout=subprocess.DEVNULL)
        if i:
            times.append(time.perf_counter() - start)
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            cpu.append(after.ru_utime - used.ru_utime + after.ru_stime - used.ru_stime)
    return times, cpu


def percentile(values: list[float], q: float) -> float:
    """The q-th percentile (0-100), nearest rank: a value that was measured."""
    ordered = sorted(values)
    return ordered[max(0, math.ceil(q / 100 * len(ordered)) - 1)]


def ms(seconds: float) -> str:
    return f"{1000 * seconds:.0f} ms"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--switches", type=int, default=40,
                        help="screen switches (half of them back to the sweeps screen)")
    parser.add_argument("--idle", type=float, default=20.0, help="seconds of idle per screen")
    parser.add_argument("--shows", type=int, default=5, help="runs of slopetui show")
    parser.add_argument("--queued", type=int, default=1000,
                        help="runs left for the workers to compute while measuring")
    parser.add_argument("--keep", action="store_true", help="keep the temporary store")
    parser.add_argument("--markdown", type=Path, help="also write the targets' table here")
    parser.add_argument("--no-bytecode-cache", dest="bytecode", action="store_false",
                        help="leave $PYTHONDONTWRITEBYTECODE and $PYTHONPYCACHEPREFIX as they are")
    args = parser.parse_args()
    if shutil.which("tmux") is None:
        raise SystemExit("bench_tui needs tmux")
    folder = Path(tempfile.mkdtemp(prefix="slopetui-bench-tui-"))
    url = f"sqlite:///{folder / 'bench.db'}"
    env = {**os.environ, "SLOPETUI_DB": url}
    if args.bytecode:
        env.pop("PYTHONDONTWRITEBYTECODE", None)
        env["PYTHONPYCACHEPREFIX"] = str(folder / "pycache")
    pool = None
    load_before = os.getloadavg()[0]
    try:
        start = time.perf_counter()
        sweep, second_last = build_store(url, args.queued)
        print(f"store: sweep {sweep}, 100 x 100, {10_000 - args.queued} runs given results, "
              f"{args.queued} queued, below a 5 x 5 sweep done "
              f"({time.perf_counter() - start:.0f} s)", flush=True)
        log = open(folder / "pool.log", "w")  # noqa: SIM115 - the pool's, closed with it
        pool = subprocess.Popen(slopetui_cmd("worker", "--batch", "8", "--log",
                                             str(folder / "worker.log")),
                                env=env, stdout=log, stderr=subprocess.STDOUT,
                                start_new_session=True)
        first = done_count(url, sweep)
        deadline = time.monotonic() + 600
        while done_count(url, sweep) == first:  # compiling the kernels, then the first batch
            if time.monotonic() > deadline or pool.poll() is not None:
                raise RuntimeError(f"the pool computed nothing: see {folder / 'pool.log'}")
            time.sleep(2)
        print(f"pool busy: its first runs are done ({time.perf_counter() - start:.0f} s)",
              flush=True)
        # the application has the tmux server's environment (this process's) and these
        app_env = [f"-e{name}={env[name]}" for name in
                   ("SLOPETUI_DB", "PYTHONPATH", "PYTHONPYCACHEPREFIX") if name in env]
        command = " ".join(slopetui_cmd("--no-workers"))
        if args.bytecode:
            command = f"env -u PYTHONDONTWRITEBYTECODE {command}"
        tmux("new-session", "-d", "-s", SESSION, "-x", str(SIZE[0]), "-y", str(SIZE[1]),
             *app_env, command)
        app_pid = int(tmux("list-panes", "-t", SESSION, "-F", "#{pane_pid}").split()[0])
        opened = wait_for(MARKERS["1"], timeout=120)
        print(f"application open: diagram on screen after {opened:.1f} s", flush=True)
        time.sleep(3)
        visits = {key: switch(key, app_pid)[0] for key in ("2", "1", "4", "1")}  # builds 2, 4
        print(f"first visits (build the screen): queue {ms(visits['2'])}, branches "
              f"{ms(visits['4'])}", flush=True)
        time.sleep(3)
        cpu = cpu_seconds(app_pid)
        lat, during = switches(args.switches, app_pid)
        cpu = (cpu_seconds(app_pid) - cpu) / args.switches
        tmux("send-keys", "-t", SESSION, "1")
        wait_for(MARKERS["1"])
        time.sleep(3)
        idle_sweeps = idle_share(app_pid, args.idle)  # the first row: the big sweep
        tmux("send-keys", "-t", SESSION, "Down")  # the second row: the small sweep
        wait_until_shown(lambda text: (run := cursor_run(text)) is not None
                         and run <= second_last, "the second sweep's diagram")
        time.sleep(3)
        idle_second = idle_share(app_pid, args.idle)
        tmux("send-keys", "-t", SESSION, "2")
        wait_for(MARKERS["2"])
        time.sleep(3)
        idle_queue = idle_share(app_pid, args.idle)
        tmux("send-keys", "-t", SESSION, "C-q")
        shows, show_cpu = show_times(env, sweep, args.shows)
        busy = done_count(url, sweep) - first
        left = 10_000 - done_count(url, sweep)
    finally:
        subprocess.run(["tmux", "-L", SOCKET, "kill-server"], capture_output=True)
        if pool is not None and pool.poll() is None:
            pool.send_signal(signal.SIGINT)  # the pool gives its runs back and stops
            try:
                pool.wait(timeout=60)
            except subprocess.TimeoutExpired:
                os.killpg(pool.pid, signal.SIGKILL)
                pool.wait()
        if not args.keep:
            shutil.rmtree(folder, ignore_errors=True)
        else:
            print(f"kept: {folder}")
    every = [t for values in lat.values() for t in values]
    load_after = os.getloadavg()[0]
    print()
    print(f"100 x 100 sweep at {SIZE[0]} x {SIZE[1]}, 2 workers busy ({busy} runs finished "
          f"while measuring, {left} left)")
    print(f"load average (1 min) {load_before:.1f} before, {load_after:.1f} after; bytecode "
          f"{'cached' if args.bytecode else 'as the environment has it'}")
    print(f"{'measure':<38} {'median':>8} {'p95':>8} {'max':>8} {'n':>4}")
    for key, name in (("1", "switch to sweeps (diagram)"), ("2", "switch to queue"),
                      ("4", "switch to branches")):
        values = lat[key]
        print(f"{name:<38} {ms(statistics.median(values)):>8} "
              f"{ms(percentile(values, 95)):>8} {ms(max(values)):>8} {len(values):>4}")
    print(f"{'every switch':<38} {ms(statistics.median(every)):>8} "
          f"{ms(percentile(every, 95)):>8} {ms(max(every)):>8} {len(every):>4}")
    print(f"{'application CPU during a switch':<38} {ms(statistics.median(during)):>8} "
          f"{ms(percentile(during, 95)):>8} {ms(max(during)):>8} {len(during):>4}")
    print(f"{'application CPU per switch, all told':<38} {ms(cpu):>8}  (its refreshes "
          "between switches included)")
    print(f"{'first visit of queue / branches':<38} {ms(visits['2']):>8} {ms(visits['4']):>8}")
    print(f"{'idle CPU, sweeps screen, first row':<38} {100 * idle_sweeps:>7.1f}% of a core "
          f"over {args.idle:g} s")
    print(f"{'idle CPU, sweeps screen, second row':<38} {100 * idle_second:>7.1f}% of a core "
          f"over {args.idle:g} s")
    print(f"{'idle CPU, queue screen in view':<38} {100 * idle_queue:>7.1f}% of a core "
          f"over {args.idle:g} s")
    print(f"{'slopetui show (wall, fresh process)':<38} best {min(shows):.2f} s, "
          f"median {statistics.median(shows):.2f} s of {len(shows)}; CPU median "
          f"{statistics.median(show_cpu):.2f} s, best {min(show_cpu):.2f} s")
    if args.markdown:
        p95, idle = percentile(every, 95), max(idle_sweeps, idle_second, idle_queue)
        show = statistics.median(shows)
        args.markdown.write_text("\n".join([
            f"| measure (100 × 100 sweep, 120 × 40, 2 workers busy; load {load_before:.1f} "
            f"→ {load_after:.1f}) | figure | target |",
            "|---|---:|---|",
            f"| screen switch, median / p95 / max ({len(every)} switches) | "
            f"{ms(statistics.median(every))} / **{ms(p95)}** / {ms(max(every))} | p95 ≤ 150 ms: "
            f"{'met' if p95 <= 0.150 else '**not met**'} |",
            "| switch to sweeps / queue / branches, median; p95 | "
            + " / ".join(ms(statistics.median(lat[k])) for k in ("1", "2", "4")) + "; "
            + " / ".join(ms(percentile(lat[k], 95)) for k in ("1", "2", "4"))
            + f" ({' / '.join(str(len(lat[k])) for k in ('1', '2', '4'))} switches) | |",
            f"| application CPU per switch, median | {ms(statistics.median(during))} | |",
            "| idle application, sweeps screen (first row / second row selected) / queue "
            f"screen in view | {100 * idle_sweeps:.1f}% / {100 * idle_second:.1f}% / "
            f"{100 * idle_queue:.1f}% of a core | ≤ 5%: "
            f"{'met' if idle <= 0.05 else '**not met**'} |",
            f"| `slopetui show`, median of {len(shows)} (best) | **{show:.2f} s** "
            f"({min(shows):.2f} s) | ≤ 1 s: {'met' if show <= 1.0 else '**not met**'} |",
            f"| `slopetui show`, CPU median (best) | {statistics.median(show_cpu):.2f} s "
            f"({min(show_cpu):.2f} s) | |"]) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
