"""``slopetui status``: progress per sweep and the live workers.

The % column counts done runs only (runs with a result): failed runs (fail) and runs
cancelled before they ran (canc) have their own columns, so a sweep whose runs all failed
reads 0%, status failed.

An adaptive sweep says where its refinement is before its name: ``[level 2/3]`` while
its levels run (done/total counts the runs of the levels queued so far against the
final lattice), ``[612 computed, 3484 inferred]`` once refined. ``--json`` adds the
keys ``adaptive_levels``, ``level``, ``refined``, ``computed`` and ``inferred``.

A pool of this host that has no live worker yet is shown as starting: it warms up (loads
numba's kernels, or compiles them after an install, ~20-45 s) before its workers register,
and ``worker --detach`` returns at once, so "no live workers" would be wrong right after
it. It is known from its pool file (slopetui.queue.local_pool); ``--json``:
``starting_pools``.
"""

from __future__ import annotations

import argparse
from typing import TYPE_CHECKING

from slopetui.cli.options import open_db, sweep_arg
from slopetui.cli.worker_lines import worker_line
from slopetui.display_text import terminal_safe
from slopetui.duration_text import duration_text
from slopetui.json_text import json_text

if TYPE_CHECKING:
    from slopetui.sweeps.progress import SweepProgress


def handle(args: argparse.Namespace) -> int:
    from slopetui.queue import registry
    from slopetui.queue.local_pool import local_pools
    from slopetui.queue.workers_table import live_workers
    from slopetui.sweeps.control import UnknownSweep
    from slopetui.sweeps.progress import claimed_line, sweep_progress

    ids = [sweep_arg(text) for text in args.sweeps]  # before the database opens
    db = open_db(args)
    sweeps = sweep_progress(db, ids or None)
    missing = sorted(set(ids) - {p.id for p in sweeps})
    if missing:  # not "no sweeps yet": the store has sweeps, just not these
        raise UnknownSweep(missing[0])
    if not (args.all or ids):
        sweeps = [p for p in sweeps if p.status in ("active", "paused")] or sweeps[:5]
    workers = live_workers(db)
    starting = [p for p in local_pools(db)[0] if not p.workers]  # warming up (docstring)
    kinds = list(registry.activity(db))  # continuations, hysteresis sweeps
    if args.json:  # json_text escapes control and non-ASCII characters: safe as it is
        print(json_text({
            "sweeps": [{"id": p.id, "name": p.name, "axes": p.axes, "status": p.status,
                        "total": p.total, "counts": p.counts, "cached": p.cached,
                        "runs_per_min": p.runs_per_min, "eta_s": p.eta_s,
                        "adaptive_levels": p.adaptive_levels, "level": p.level,
                        "refined": p.refined, "computed": p.computed, "inferred": p.inferred}
                       for p in sweeps],
            **{kind.key: seen.counts for kind, seen in kinds},
            "workers": [{"id": w.id, "run_id": w.run_id,
                         **{kind.id_key: seen.held.get(w.id) for kind, seen in kinds},
                         "jobs_done": w.jobs_done, "heartbeat_age_s": w.heartbeat_age_s}
                        for w in workers],
            "starting_pools": [{"pid": p.pid, "uptime_s": p.uptime_s, "log": p.log}
                               for p in starting]}))
        return 0
    if not sweeps:
        print("no sweeps yet: slopetui submit --help")
    else:
        print(f"{'id':>4}  {'status':9} {'axes':9} {'done/total':>13} {'%':>4} {'run':>3} "
              f"{'fail':>4} {'canc':>4} {'runs/min':>8} {'eta':>7}  name")
        for p in sweeps:  # stored text (names, statuses, worker ids) through terminal_safe
            # done only: a sweep whose runs all failed is at 0%, not 100% (its fail column
            # and its status say the rest)
            pct = 100 * p.done // max(p.total, 1)
            print(f"{p.id:>4}  {terminal_safe(p.status):9} {terminal_safe(p.axes):9} "
                  f"{p.done:>6}/{p.total:<6} {pct:>4} {p.running:>3} {p.failed:>4} "
                  f"{p.cancelled:>4} {p.runs_per_min:>8.1f} "
                  f"{duration_text(p.eta_s if workers else None):>7}  {adaptive_stage(p)}"
                  f"{terminal_safe(p.name)}")
    for kind, seen in kinds:
        waiting = {k: n for k, n in seen.counts.items() if k in ("queued", "running")}
        if waiting:
            print(f"{kind.plural}: " + ", ".join(f"{n} {k}" for k, n in sorted(waiting.items()))
                  + f" ({kind.shown_by})")
    if held := claimed_line(db, len(workers)):
        print(held)
    print()
    for pool in starting:
        up = "" if pool.uptime_s is None else f", up {duration_text(pool.uptime_s)}"
        print(f"pool {pool.pid} on this host: starting{up} (it loads the numba kernels, or "
              "compiles them after an install, ~20-45 s; then its workers register)")
    if not workers and not starting:
        print("no live workers: start a pool with `slopetui worker --detach`")
    for w in workers:
        print(worker_line(w, {kind.label: seen.held for kind, seen in kinds}))
    return 0


def adaptive_stage(p: SweepProgress) -> str:
    """"[level 2/3] " or "[612 computed, 3484 inferred] " for an adaptive sweep."""
    if p.adaptive_levels is None:
        return ""
    if p.refined:
        return f"[{p.computed} computed, {p.inferred} inferred] "
    return f"[{p.stage}] "
