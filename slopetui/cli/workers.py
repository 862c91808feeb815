"""``slopetui workers``: the worker pools of a store and what each worker runs; and the stop
behind ``slopetui worker --stop``.

Everything comes from the store's workers table and the pool files of this host
(slopetui.queue.local_pool), so it works from any login, over SSH too. A pool on another
host is known by its workers' rows only: its pid is not in the database, and it cannot be
signalled from here.

Worker ids and host names are stored text that any host sharing the store can write: they
are printed through ``terminal_safe`` (``--json`` escapes them itself).
"""

from __future__ import annotations

import argparse
import os
import signal
import socket
import sys
import time
from typing import TYPE_CHECKING

from slopetui.cli.options import open_db
from slopetui.cli.worker_lines import worker_line
from slopetui.display_text import terminal_safe
from slopetui.duration_text import duration_text
from slopetui.json_text import json_text

if TYPE_CHECKING:
    from slopetui.queue.local_pool import LocalPool
    from slopetui.queue.workers_table import WorkerInfo
    from slopetui.store.database import Database

#: While `worker --stop` waits, it says what it waits for at once, then this often (s).
SAY_EVERY_S = 10.0



def _remote(db: Database) -> dict[str, list[WorkerInfo]]:
    """Live workers of other hosts, by host."""
    from slopetui.queue.workers_table import live_workers
    here = socket.gethostname()
    hosts: dict[str, list[WorkerInfo]] = {}
    for w in live_workers(db):
        if w.host != here:
            hosts.setdefault(w.host, []).append(w)
    return hosts


def _worker_json(w: WorkerInfo) -> dict[str, object]:
    return {"id": w.id, "pid": w.pid, "run_id": w.run_id, "jobs_done": w.jobs_done,
            "heartbeat_age_s": w.heartbeat_age_s}


def handle(args: argparse.Namespace) -> int:
    from slopetui.queue import registry
    from slopetui.queue.local_pool import local_pools
    from slopetui.store.queries import database_now
    db = open_db(args)
    held = {kind.label: seen.held for kind, seen in registry.activity(db)}
    pools, orphans = local_pools(db)
    remote = _remote(db)
    now = database_now(db)
    here = socket.gethostname()
    if args.json:
        print(json_text({
            "pools": [{"host": here, "pid": p.pid, "uptime_s": p.uptime_s, "log": p.log,
                       "workers": [_worker_json(w) for w in p.workers]} for p in pools]
                     + [{"host": host, "pid": None,
                         "uptime_s": max((now - w.started_at).total_seconds() for w in ws),
                         "log": None, "workers": [_worker_json(w) for w in ws]}
                        for host, ws in sorted(remote.items())],
            "orphans": [_worker_json(w) for w in orphans]}))
        return 0
    if not (pools or orphans or remote):
        print("no worker pool of this store is running: start one with "
              "`slopetui worker --detach`")
        return 0
    for p in pools:
        state = f"{len(p.workers)} workers" if p.workers else "starting (no worker yet)"
        log = f"; log {p.log}" if p.log else ""
        print(f"pool {p.pid} on {here} (this host), up {duration_text(p.uptime_s)}, {state}{log}")
        for w in p.workers:
            print(f"  {worker_line(w, held)}")
    for host, ws in sorted(remote.items()):
        up = max((now - w.started_at).total_seconds() for w in ws)
        print(f"workers on {terminal_safe(host)} (another host: their pool's pid is not known here), up "
              f"{duration_text(up)}, {len(ws)} workers")
        for w in ws:
            print(f"  {worker_line(w, held)}")
    for w in orphans:
        print(f"orphan worker {terminal_safe(w.id)} (its pool is gone; `slopetui worker --stop` stops it)")
    return 0


# --- slopetui worker --stop ---------------------------------------------------------------

def _waiting_for(pool: LocalPool) -> str:
    if not pool.workers:
        return f"pool {pool.pid} (starting, no worker yet)"
    doing = ", ".join(f"{terminal_safe(w.id)} on run {w.run_id}" if w.run_id
                      else f"{terminal_safe(w.id)} idle"
                      for w in pool.workers)
    return f"pool {pool.pid}: {doing}"


def stop_pools(db: Database, *, now: bool = False) -> int:
    """SIGTERM the pools of the store on this host (``now``: twice), then wait for them to
    exit, saying what they still compute. 0 once none runs here; 1 if one could not be
    signalled (another user's)."""
    from slopetui.queue.local_pool import is_alive, local_pools, signal_pool
    here = socket.gethostname()
    for host, ws in sorted(_remote(db).items()):
        shown = terminal_safe(host)
        print(f"{len(ws)} workers of this store run on {shown}: they cannot be signalled "
              f"from {here}; run `slopetui worker --stop` on {shown}", file=sys.stderr)
    pools, orphans = local_pools(db)
    if not (pools or orphans):
        print(f"no worker pool of this store runs on {here}")
        return 0
    how = ("now: the running runs go back to the queue" if now
           else "the runs being computed finish first")
    targets: dict[int, str] = {}
    status = 0
    for pool in pools:
        try:
            signal_pool(pool.pid, now=now)
        except ProcessLookupError:
            continue
        except PermissionError:
            print(f"pool {pool.pid} belongs to another user: cannot signal it",
                  file=sys.stderr)
            status = 1
            continue
        targets[pool.pid] = f"pool {pool.pid}"
        print(f"stopping pool {pool.pid} ({len(pool.workers)} workers; {how})")
    for w in orphans:  # no pool to decide for them: signal the worker itself
        try:
            os.kill(w.pid, signal.SIGTERM)
            if now:
                time.sleep(0.3)
                os.kill(w.pid, signal.SIGTERM)
        except (ProcessLookupError, PermissionError):
            continue
        targets[w.pid] = f"orphan worker {terminal_safe(w.id)}"
        print(f"stopping orphan worker {terminal_safe(w.id)} ({how})")
    if not targets:
        return status
    if not now:
        print("waiting (Ctrl-C stops waiting, not the pool; `slopetui worker --stop --now` "
              "gives the running runs back at once)")
    said = -SAY_EVERY_S
    try:
        while targets:
            time.sleep(0.2)
            for pid in [pid for pid in targets if not is_alive(pid)]:
                print(f"{targets.pop(pid)} stopped")
            if targets and time.monotonic() - said >= SAY_EVERY_S:
                said = time.monotonic()
                pools, _ = local_pools(db)
                for pool in pools:
                    if pool.pid in targets:
                        print(f"waiting for {_waiting_for(pool)}")
    except KeyboardInterrupt:
        print("stopped waiting; the pools are still stopping (see `slopetui workers`)",
              file=sys.stderr)
        return 130
    return status
