"""``slopetui worker``: run the worker pool (in the foreground, or detached)."""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from slopetui.cli.options import UsageError, add_db_option
from slopetui.queue import jobs
from slopetui.queue.local_pool import default_log, start_detached_pool
from slopetui.queue.pool import default_jobs, run_pool
from slopetui.queue.worker_process import WorkerOptions
from slopetui.store.database import Database

#: A batch is held in memory whole: the paper's window (1000 time units at 0.01) is 4 MB a
#: run, so 256 runs take 1 GB per worker. Beyond the kernel's 16 slots, a larger batch only
#: keeps the slots full when some runs end early.
MAX_BATCH = 256


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "worker", help="run the worker pool that computes queued runs",
        description="Run N worker processes that claim queued runs, compute them and store "
                    "the results. Ctrl-C or SIGTERM: running jobs finish, then the pool "
                    "exits; a second signal gives them back to the queue at once.")
    p.add_argument("-j", "--jobs", type=int, default=default_jobs(), metavar="N",
                   help=f"worker processes (default: the cores available, {default_jobs()})")
    p.add_argument("--log", metavar="FILE", help=f"log file (default {default_log()}; "
                                                 "the foreground pool also logs to stderr)")
    p.add_argument("--detach", action="store_true",
                   help="run in the background, in its own session: it survives the end of "
                        "the SSH session (prints its pid)")
    p.add_argument("--exit-when-idle", action="store_true",
                   help="exit once no queued or running run is left")
    p.add_argument("--lease", type=float, default=jobs.LEASE_S, metavar="S",
                   help=f"seconds without heartbeat before a run is requeued "
                        f"(default {jobs.LEASE_S:g})")
    p.add_argument("--heartbeat", type=float, default=jobs.HEARTBEAT_S, metavar="S",
                   help=f"seconds between heartbeats (default {jobs.HEARTBEAT_S:g})")
    p.add_argument("--max-attempts", type=int, default=jobs.MAX_ATTEMPTS, metavar="N",
                   help=f"attempts before a run is marked failed (default {jobs.MAX_ATTEMPTS})")
    p.add_argument("--batch", type=int, default=WorkerOptions.batch, metavar="N",
                   help="runs with the same solver settings claimed and computed together by "
                        f"the batched kernels (default {WorkerOptions.batch}; 1 computes one "
                        f"run at a time; at most {MAX_BATCH})")
    add_db_option(p)
    p.set_defaults(handler=handle)


def _check(args: argparse.Namespace) -> None:
    if args.jobs < 1:
        raise UsageError(f"--jobs must be >= 1, got {args.jobs}")
    if not 1 <= args.batch <= MAX_BATCH:
        raise UsageError(f"--batch must be between 1 and {MAX_BATCH}, got {args.batch}")
    if args.max_attempts < 1:
        raise UsageError(f"--max-attempts must be >= 1, got {args.max_attempts}")
    if not args.heartbeat > 0:
        raise UsageError(f"--heartbeat must be > 0 seconds, got {args.heartbeat}")
    if not args.lease >= 2 * args.heartbeat:
        raise UsageError(f"--lease must be >= 2 x --heartbeat = {2 * args.heartbeat:g} s, "
                         f"got {args.lease}")


def _detach(args: argparse.Namespace, db: Database, log: Path) -> int:
    extra = ["--lease", str(args.lease), "--heartbeat", str(args.heartbeat),
             "--max-attempts", str(args.max_attempts), "--batch", str(args.batch)]
    if args.exit_when_idle:
        extra.append("--exit-when-idle")
    pid, log = start_detached_pool(db, jobs=args.jobs, log=log, extra=tuple(extra))
    print(f"worker pool started in the background: pid {pid}, {args.jobs} workers")
    print(f"log: {log}")
    print(f"stop it: kill {pid}   (running jobs finish; kill it twice to requeue them)")
    return 0


def handle(args: argparse.Namespace) -> int:
    _check(args)
    db = Database(args.db)  # open (and migrate) now: a bad URL fails here, in the foreground
    url = db.url.render_as_string(hide_password=False)
    db.dispose()
    log = Path(args.log) if args.log else default_log()
    log.parent.mkdir(parents=True, exist_ok=True, mode=0o700)
    if args.detach:
        return _detach(args, db, log)
    if sys.stderr.isatty():
        print(f"worker pool: {args.jobs} workers on {db.display_url}; log {log}; Ctrl-C stops",
              file=sys.stderr)
    opts = WorkerOptions(db_url=url, log_path=str(log), heartbeat_s=args.heartbeat,
                         lease_s=args.lease, max_attempts=args.max_attempts,
                         exit_when_idle=args.exit_when_idle, batch=args.batch)
    os.environ.setdefault("PYTHONUNBUFFERED", "1")
    return run_pool(opts, args.jobs)
