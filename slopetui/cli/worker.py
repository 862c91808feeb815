"""``slopetui worker``: run the worker pool (in the foreground, or detached), or stop it.

The pool and its kernels are imported in the handler, not here: ``slopetui --help`` must
not pay for numba.
"""

from __future__ import annotations

import argparse
import math
import os
import re
import sys
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING

from slopetui.cli.arguments.worker import (
    CONNECTIONS_RANGE,
    HEARTBEAT_RANGE,
    MAX_ATTEMPTS_RANGE,
    MAX_BATCH,
    MAX_IDLE_GRACE_S,
    MAX_JOBS,
    MAX_LEASE_S,
    MEMORY_RANGE,
)
from slopetui.cli.options import UsageError
from slopetui.cli.workers import stop_pools
from slopetui.queue.idle_exit import Owner
from slopetui.queue.local_pool import PoolRunning, default_log, local_pools, start_detached_pool, store_key
from slopetui.queue.pool import run_pool
from slopetui.queue.worker_process import WorkerOptions
from slopetui.store.open import open_store
from slopetui.sweeps.adaptive import advance_all
from slopetui.sweeps.progress import PoolProgress

if TYPE_CHECKING:
    from slopetui.queue.local_pool import LocalPool
    from slopetui.store.database import Database

#: --owner-pid: Linux's largest pid (PID_MAX_LIMIT).
MAX_PID = 4_194_304
#: What a --host-id may hold: it is written into worker ids and log lines.
HOST_ID = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]{0,62}")


def _in_range(option: str, value: float, low: float, high: float, unit: str = "") -> None:
    """One line naming the option and its range; inf and nan are refused too."""
    if not (math.isfinite(value) and low <= value <= high):
        raise UsageError(f"{option} must be a finite number{unit} from {low:g} to {high:g}, "
                         f"got {value:g}")


def _check(args: argparse.Namespace) -> None:
    if args.now and not args.stop:
        raise UsageError("--now goes with --stop (slopetui worker --stop --now)")
    if args.stop and args.detach:
        raise UsageError("--stop and --detach exclude each other")
    _in_range("--jobs", args.jobs, 1, MAX_JOBS)
    _in_range("--batch", args.batch, 1, MAX_BATCH)
    _in_range("--memory", args.memory, *MEMORY_RANGE, unit=" of MiB")
    _in_range("--max-attempts", args.max_attempts, *MAX_ATTEMPTS_RANGE)
    _in_range("--heartbeat", args.heartbeat, *HEARTBEAT_RANGE, unit=" of seconds")
    _in_range("--connections", args.connections, *CONNECTIONS_RANGE)
    _in_range("--idle-grace", args.idle_grace, 0, MAX_IDLE_GRACE_S, unit=" of seconds")
    if args.owner_pid is not None:
        _in_range("--owner-pid", args.owner_pid, 1, MAX_PID)
    if args.host_id is not None and not HOST_ID.fullmatch(args.host_id):
        raise UsageError(f"--host-id must be 1 to 63 letters, digits, '.', '_' or '-' "
                         f"(starting with a letter or digit), got {args.host_id!r}")
    if math.isfinite(args.heartbeat):
        _in_range("--lease", args.lease, 2 * args.heartbeat, MAX_LEASE_S,
                  unit=" of seconds (at least 2 x --heartbeat)")


def _log_file(text: str) -> Path:
    """--log as a file the pool can append to, or a one-line UsageError naming it: checked
    before the store is opened, so that a refusal creates nothing (before: IsADirectoryError
    or PermissionError tracebacks from the pool). Missing folders are created later, as
    for the default log, if the nearest existing one is writable."""
    if not text.strip():
        raise UsageError(f"--log = {text!r} is empty: allowed a file name (appended to, "
                         "created 0600)")
    path = Path(text)
    if path.is_dir():
        raise UsageError(f"--log = {text!r} is a folder: allowed a file, e.g. "
                         f"{str(path / 'worker.log')!r}")
    if path.exists():  # opened to append, as the pool's logging will: nothing changes in it
        try:
            open(path, "a", encoding="utf-8").close()
        except OSError as exc:
            raise UsageError(f"--log = {text!r} cannot be written ({exc.strerror}): allowed "
                             "a file you may write") from None
        return path
    folder = path.absolute().parent
    while not folder.exists():
        folder = folder.parent
    if not folder.is_dir():
        raise UsageError(f"--log = {text!r}: {str(folder)!r} is not a folder: allowed a file "
                         "in a folder")
    try:  # a file made and removed there: os.access answers yes to root where it may not
        tempfile.TemporaryFile(dir=folder).close()  # write (/sys), or on a read-only mount
    except OSError as exc:
        raise UsageError(f"--log = {text!r} cannot be created in {str(folder)!r} "
                         f"({exc.strerror}): allowed a file in a folder you may write") from None
    return path


def _already_running(pools: list[LocalPool]) -> UsageError:
    pool = pools[0]
    state = f"{len(pool.workers)} workers" if pool.workers else "starting"
    more = f" (and {len(pools) - 1} more)" if len(pools) > 1 else ""
    return UsageError(f"a worker pool of this store already runs on this host: pid "
                      f"{pool.pid} ({state}){more}; stop it with `slopetui worker --stop`, "
                      "or pass --another-pool to start a second one")


def _detach(args: argparse.Namespace, db: Database, log: Path) -> int:
    extra = ["--lease", str(args.lease), "--heartbeat", str(args.heartbeat),
             "--max-attempts", str(args.max_attempts), "--batch", str(args.batch),
             "--memory", str(args.memory), "--connections", str(args.connections)]
    if args.host_id:
        extra += ["--host-id", args.host_id]
    if args.exit_when_idle:
        extra.append("--exit-when-idle")
    extra += ["--idle-grace", str(args.idle_grace)]
    if args.owner_pid is not None:
        extra += ["--owner-pid", str(args.owner_pid)]
    try:
        pid, log = start_detached_pool(db, jobs=args.jobs, log=log, extra=tuple(extra),
                                       another_pool=args.another_pool)
    except PoolRunning as exc:
        raise _already_running(exc.pools) from None
    print(f"worker pool started in the background: pid {pid}, {args.jobs} workers")
    # not waited for: a first start compiles the kernels for half a minute (slopetui status)
    print("starting: its workers register once it has loaded the numba kernels (compiled "
          "once after an install, ~20-45 s); `slopetui status` shows it as starting until then")
    print(f"log: {log}")
    print("see it: slopetui workers    stop it: slopetui worker --stop   (running jobs "
          "finish; --stop --now gives them back to the queue)")
    return 0


def handle(args: argparse.Namespace) -> int:
    _check(args)
    given_log = _log_file(args.log) if args.log is not None else None
    # read first, while the owner (which has just started this pool) surely still runs
    owner = None
    if args.owner_pid is not None and not args.stop:
        owner = Owner.of(args.owner_pid)
    db = open_store(args.db)  # open (and migrate) now: a bad URL fails here, in the foreground
    if args.stop:
        return stop_pools(db, now=args.now)
    url = db.url.render_as_string(hide_password=False)
    if owner is not None:  # the store's other applications count as its owner too
        from dataclasses import replace

        owner = replace(owner, store=store_key(url))
    log = given_log or default_log()
    log.parent.mkdir(parents=True, exist_ok=True, mode=0o700)
    if args.detach:
        return _detach(args, db, log)
    if not args.another_pool:
        pools, _ = local_pools(db)
        if pools:
            raise _already_running(pools)
    db.dispose()
    if sys.stderr.isatty():
        print(f"worker pool: {args.jobs} workers on {db.display_url}; log {log}; Ctrl-C stops",
              file=sys.stderr)
    opts = WorkerOptions(db_url=url, log_path=str(log), heartbeat_s=args.heartbeat,
                         lease_s=args.lease, max_attempts=args.max_attempts,
                         exit_when_idle=args.exit_when_idle, idle_grace_s=args.idle_grace,
                         owner=owner, batch=args.batch,
                         memory_mib=args.memory, idle_hook=advance_all, progress=PoolProgress,
                         host_id=args.host_id, connections=args.connections)
    os.environ.setdefault("PYTHONUNBUFFERED", "1")
    return run_pool(opts, args.jobs, exiting=True)  # a late SIGTERM cannot make it 143
