"""The worker pool: N spawned worker processes, supervised.

The pool migrates the database and warms numba's kernel cache once, serially, before it
spawns anyone (several processes compiling into one cache at once can corrupt it,
numba#10128). It restarts a worker that dies and hands the dead worker's run back to the
queue at once. SIGINT, SIGTERM or SIGHUP: the workers finish their running jobs and exit;
a second signal makes them give their jobs back to the queue and exit now.
"""

from __future__ import annotations

import logging
import multiprocessing as mp
import os
import signal
import sys
from multiprocessing.connection import wait
from multiprocessing.process import BaseProcess
from typing import Any

from slopetui.queue import jobs
from slopetui.queue.worker_process import (
    WorkerOptions,
    configure_logging,
    warm_up,
    worker_id_for,
    worker_main,
)
from slopetui.store.database import Database

log = logging.getLogger("slopetui.pool")

#: After this many deaths per worker slot the pool stops restarting workers: that is a
#: broken installation or database, not one bad run (those fail after MAX_ATTEMPTS).
MAX_QUICK_DEATHS = 5


def default_jobs() -> int:
    """The cores this process may use."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


class Pool:
    def __init__(self, opts: WorkerOptions, n_workers: int) -> None:
        self.opts, self.n_workers = opts, n_workers
        self.ctx = mp.get_context("spawn")
        self.stop, self.abort = self.ctx.Event(), self.ctx.Event()
        self.procs: dict[int, BaseProcess] = {}  # sentinel -> process
        self.deaths = 0

    def _spawn(self) -> None:
        proc = self.ctx.Process(target=worker_main, args=(self.opts, self.stop, self.abort),
                                name=f"slopetui-worker-{len(self.procs)}")
        proc.start()
        self.procs[proc.sentinel] = proc

    def _on_signal(self, signum: int, _frame: Any) -> None:
        if self.stop.is_set():
            log.info("%s again: workers give their runs back and exit",
                     signal.Signals(signum).name)
            self.abort.set()
        else:
            log.info("%s: workers finish their running jobs, then exit (again: give them "
                     "back now)", signal.Signals(signum).name)
            self.stop.set()

    def _reap(self, db: Database, proc: BaseProcess) -> None:
        proc.join()
        if proc.exitcode == 0:
            return
        wid = worker_id_for(proc.pid or 0)
        requeued, failed = jobs.requeue_worker(
            db, wid, f"worker {wid} died (exit code {proc.exitcode})", self.opts.max_attempts)
        log.error("worker %s died (exit code %s): %d runs requeued, %d failed", wid,
                  proc.exitcode, requeued, failed)
        self.deaths += 1
        if self.stop.is_set():
            return
        if self.deaths > MAX_QUICK_DEATHS * self.n_workers:
            log.error("workers keep dying; not restarting (see the errors above)")
            self.stop.set()
            return
        self._spawn()

    def run(self) -> int:
        """Run until stopped (or, with exit_when_idle, until the queue is drained)."""
        db = Database(self.opts.db_url)  # migrates a new or old database, under a lock
        log.info("pool of %d workers on %s (pid %d)", self.n_workers, db.display_url,
                 os.getpid())
        warm_up()
        for signum in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
            signal.signal(signum, self._on_signal)
        for _ in range(self.n_workers):
            self._spawn()
        while self.procs:
            for sentinel in wait(list(self.procs), timeout=1.0):
                self._reap(db, self.procs.pop(sentinel))  # type: ignore[arg-type]
        log.info("pool stopped")
        return 0


def run_pool(opts: WorkerOptions, n_workers: int) -> int:
    """Run a pool in this process; the pool's own messages also go to a terminal."""
    configure_logging(opts.log_path, echo=sys.stderr.isatty())
    return Pool(opts, n_workers).run()
