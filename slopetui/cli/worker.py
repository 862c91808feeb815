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

from slopetui.cli.options import UsageError, add_db_option
from slopetui.ops.connection_slots import DEFAULT_CONNECTIONS
from slopetui.queue import defaults
from slopetui.queue.local_pool import default_jobs, default_log

if TYPE_CHECKING:
    from slopetui.queue.local_pool import LocalPool
    from slopetui.store.database import Database

#: A batch is held in memory whole: the paper's window (1000 time units at 0.01) is 4 MB a
#: run, so 256 runs take 1 GB per worker. Beyond the kernel's 16 slots, a larger batch only
#: keeps the slots full when some runs end early.
MAX_BATCH = 256
#: More processes than this is a typo, not a machine (each one holds a database connection).
MAX_JOBS = 512
#: Heartbeats faster than this load the database for nothing; slower ones than this make
#: dead workers' runs wait (s).
HEARTBEAT_RANGE = (0.1, 600.0)
#: A lease covers at least two heartbeats, and at most a day (s).
MAX_LEASE_S = 86_400.0
MAX_ATTEMPTS_RANGE = (1, 100)
#: A worker's memory budget for a batch (MiB): 64 MiB holds a few paper runs (~10 MB
#: each); 512 GiB is beyond any node we run on.
MEMORY_RANGE = (64, 512 * 1024)
#: A pool's connection budget on a server database (slopetui.ops.connection_slots).
CONNECTIONS_RANGE = (1, 64)
#: --idle-grace: up to a day (s).
MAX_IDLE_GRACE_S = 86_400.0
#: --owner-pid: Linux's largest pid (PID_MAX_LIMIT).
MAX_PID = 4_194_304
#: What a --host-id may hold: it is written into worker ids and log lines.
HOST_ID = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]{0,62}")


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "worker", help="run (or stop) the worker pool that computes queued runs",
        description="Run N worker processes that claim queued runs, compute them and store "
                    "the results. Ctrl-C, SIGTERM or SIGHUP to the pool: the runs being "
                    "computed finish, then the pool exits; a second signal gives them back "
                    "to the queue at once. SIGTERM to one worker stops that worker alone. "
                    "Progress goes to stderr (and the log). Exit status: 0 after a stop, 1 "
                    "if the pool gave up because workers kept dying, 2 for bad options or "
                    "a pool of the store already running on this host.")
    p.add_argument("-j", "--jobs", type=int, default=default_jobs(), metavar="N",
                   help=f"worker processes, 1 to {MAX_JOBS} (default: the cores available, "
                        f"{default_jobs()})")
    p.add_argument("--log", metavar="FILE", help=f"log file, created 0600 (default "
                                                 f"{default_log()}; the foreground pool's "
                                                 "own messages also go to stderr)")
    p.add_argument("--detach", action="store_true",
                   help="run in the background, in its own session: it survives the end of "
                        "the SSH session (prints its pid)")
    p.add_argument("--another-pool", action="store_true",
                   help="start even though a pool of this store already runs on this host "
                        "(by default that is refused: its workers would share the cores)")
    p.add_argument("--stop", action="store_true",
                   help="stop the pools of this store on this host (SIGTERM: the runs being "
                        "computed finish) and wait until they have exited")
    p.add_argument("--now", action="store_true",
                   help="with --stop: give the running runs back to the queue and exit at "
                        "once (a second SIGTERM)")
    p.add_argument("--exit-when-idle", action="store_true",
                   help="exit once nothing is queued or running; while queued runs are left "
                        "only in paused sweeps, once nothing has been claimable for "
                        "--idle-grace seconds")
    p.add_argument("--idle-grace", type=float, default=defaults.IDLE_GRACE_S, metavar="S",
                   help=f"with --exit-when-idle or --owner-pid: seconds with nothing "
                        f"claimable before the pool leaves while work may still come back "
                        f"(a paused sweep, the owner's user), 0 to {MAX_IDLE_GRACE_S:g} "
                        f"(default {defaults.IDLE_GRACE_S:g})")
    p.add_argument("--owner-pid", type=int, metavar="PID",
                   help="the pool works for process PID (the application starts its pool "
                        "so): once PID has exited, the pool leaves when nothing has been "
                        "claimable or running for --idle-grace seconds")
    p.add_argument("--lease", type=float, default=defaults.LEASE_S, metavar="S",
                   help=f"seconds without heartbeat before a run is requeued, from 2 x "
                        f"--heartbeat to {MAX_LEASE_S:g} (default {defaults.LEASE_S:g})")
    p.add_argument("--heartbeat", type=float, default=defaults.HEARTBEAT_S, metavar="S",
                   help=f"seconds between heartbeats, {HEARTBEAT_RANGE[0]:g} to "
                        f"{HEARTBEAT_RANGE[1]:g} (default {defaults.HEARTBEAT_S:g})")
    p.add_argument("--max-attempts", type=int, default=defaults.MAX_ATTEMPTS, metavar="N",
                   help=f"attempts before a run is marked failed, {MAX_ATTEMPTS_RANGE[0]} to "
                        f"{MAX_ATTEMPTS_RANGE[1]} (default {defaults.MAX_ATTEMPTS})")
    p.add_argument("--batch", type=int, default=defaults.DEFAULT_BATCH, metavar="N",
                   help="runs with the same solver settings claimed together, 1 to "
                        f"{MAX_BATCH} (default {defaults.DEFAULT_BATCH}); Euler batches go "
                        "through the batched kernel, RK4 runs are computed and stored one "
                        "by one")
    p.add_argument("--memory", type=int, default=defaults.MEMORY_MIB, metavar="MIB",
                   help=f"memory the runs of a batch may take together, {MEMORY_RANGE[0]} to "
                        f"{MEMORY_RANGE[1]} MiB (default {defaults.MEMORY_MIB}): a batch of "
                        "long windows is cut to fit, the rest left queued")
    p.add_argument("--connections", type=int, default=DEFAULT_CONNECTIONS, metavar="N",
                   help=f"on a PostgreSQL store: database connections the pool and its "
                        f"workers hold at once, {CONNECTIONS_RANGE[0]} to "
                        f"{CONNECTIONS_RANGE[1]}, whatever -j (default {DEFAULT_CONNECTIONS}; "
                        "a worker needs one only to claim and to write)")
    p.add_argument("--host-id", metavar="NAME",
                   help="the host name the workers' ids carry (default: this host's name); "
                        "several pools on one machine with distinct names stand for "
                        "several hosts (`workers` and `worker --stop` then count them as "
                        "another host's)")
    add_db_option(p)
    p.set_defaults(handler=handle)


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
    from slopetui.queue.local_pool import PoolRunning, start_detached_pool
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
    from slopetui.store.open import open_store
    # read first, while the owner (which has just started this pool) surely still runs
    owner = None
    if args.owner_pid is not None and not args.stop:
        from slopetui.queue.idle_exit import Owner
        owner = Owner.of(args.owner_pid)
    db = open_store(args.db)  # open (and migrate) now: a bad URL fails here, in the foreground
    if args.stop:
        from slopetui.cli.workers import stop_pools
        return stop_pools(db, now=args.now)
    url = db.url.render_as_string(hide_password=False)
    if owner is not None:  # the store's other applications count as its owner too
        from dataclasses import replace

        from slopetui.queue.local_pool import store_key
        owner = replace(owner, store=store_key(url))
    log = given_log or default_log()
    log.parent.mkdir(parents=True, exist_ok=True, mode=0o700)
    if args.detach:
        return _detach(args, db, log)
    if not args.another_pool:
        from slopetui.queue.local_pool import local_pools
        pools, _ = local_pools(db)
        if pools:
            raise _already_running(pools)
    db.dispose()
    from slopetui.queue.pool import run_pool
    from slopetui.queue.worker_process import WorkerOptions
    from slopetui.sweeps.adaptive import advance_all
    from slopetui.sweeps.progress import PoolProgress
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
