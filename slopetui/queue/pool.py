"""The worker pool: N spawned worker processes, supervised.

The pool migrates the database and warms numba's kernel cache once, serially, before it
spawns anyone (several processes compiling into one cache at once can corrupt it,
numba#10128), unless a previous warm-up's marker says the cache holds every kernel
(slopetui.queue.warm_up.pool_warm_up). It restarts a worker that dies and hands the dead
worker's runs back to the queue at once. Its workers run one BLAS thread each unless the
user set a thread count (slopetui.queue.blas_threads).

Signals. SIGINT, SIGTERM or SIGHUP: the workers finish the runs in their kernels and exit;
a second signal makes them give their runs back to the queue and exit now. The handlers do
nothing (stop_signals.SignalPipe): the main loop, which waits on the workers' sentinels
and on the signal pipe together, counts the signals and sets the workers' ``stop`` or
``abort`` Event itself. A signal handler that set an Event could deadlock on the Event's
lock (the handler runs in the main thread, between two bytecodes of whatever it does).
The workers only ever read the Events (is_set), never wait on them: multiprocessing's
Event.set() waits until every process sleeping in Event.wait() has woken, so one worker
stuck in a handler would hang the pool's set(), and with it the whole pool.

A worker that exits with status 0 left on purpose (a SIGTERM sent to it alone, an idle
queue with exit_when_idle or once the pool's owner has quit: slopetui.queue.idle_exit):
it is not replaced and not counted as a death. The pool exits when its last worker has.

A store that refuses writes (read-only, a full disk: slopetui.store.write_checks) is
named in one line before the warm-up; met later, by a worker's write, the worker says so
in one line and exits with WRITE_REFUSED, and the pool stops.

Exit status: 0 after a stop, 1 when it gave up because workers kept dying (DEATH_WINDOW_S)
or the store refused writes, so that a supervisor such as systemd's Restart=on-failure
starts it again.
"""

from __future__ import annotations

import logging
import multiprocessing as mp
import os
import signal
import sys
import time
from collections import deque
from collections.abc import Callable
from dataclasses import replace
from multiprocessing.connection import wait
from multiprocessing.process import BaseProcess

from slopetui.ops.connection_slots import remove_slots_folder, slots_folder
from slopetui.queue import registry
from slopetui.queue.blas_threads import one_blas_thread
from slopetui.queue.local_pool import default_jobs, remove_pool_file, write_pool_file
from slopetui.queue.stop_signals import STOP_SIGNALS, SignalPipe, block_stop_signals
from slopetui.queue.warm_up import pool_warm_up
from slopetui.queue.worker_process import (
    WRITE_REFUSED,
    WorkerOptions,
    configure_logging,
    worker_id_for,
    worker_main,
)
from slopetui.store.database import Database
from slopetui.store.integrity import integrity_problems
from slopetui.store.open import open_store
from slopetui.store.write_checks import refuses_writes

__all__ = ["DeathWindow", "Pool", "default_jobs", "run_pool"]

log = logging.getLogger("slopetui.pool")

#: The pool gives up when more than MAX_DEATHS_PER_WORKER x N workers died within the last
#: DEATH_WINDOW_S seconds. A broken installation or database kills every worker within
#: seconds of its start (a warm-up from numba's cache takes 1-3 s), so a crash loop passes
#: that bound in about 15 s whatever N is. A run that crashes its worker kills at most
#: max_attempts (3) workers before it is marked failed, and deaths spread over hours (the
#: OOM killer, an admin's kill -9) drop out of the window, so neither makes it give up.
DEATH_WINDOW_S = 60.0
MAX_DEATHS_PER_WORKER = 5
#: After an abort (second signal), a worker that has not exited after this long is killed
#: (its runs are handed back by the pool): the abort must end, even on a stuck worker (s).
ABORT_GRACE_S = 10.0
#: A progress line ("12/240 runs done, ...") at most this often, when something changed (s).
PROGRESS_S = 10.0


class DeathWindow:
    """Worker deaths within the last ``window_s`` seconds."""

    def __init__(self, limit: int, window_s: float = DEATH_WINDOW_S) -> None:
        self.limit, self.window_s = limit, window_s
        self.times: deque[float] = deque()

    def add(self, now: float) -> bool:
        """Record a death at ``now`` (monotonic seconds); True if there were more than
        ``limit`` within the window."""
        self.times.append(now)
        while self.times[0] <= now - self.window_s:
            self.times.popleft()
        return len(self.times) > self.limit


class Progress:
    """Logs the line of ``line()`` (see worker_process.ProgressSource: WorkerOptions.progress)
    when there is one, at most every PROGRESS_S seconds."""

    def __init__(self, line: Callable[[], str | None], every_s: float = PROGRESS_S) -> None:
        self.line, self.every_s = line, every_s
        self.next_at = 0.0

    def tick(self, force: bool = False) -> None:
        now = time.monotonic()
        if now < self.next_at and not force:
            return
        self.next_at = now + self.every_s
        try:
            text = self.line()
        except Exception as exc:  # progress is a courtesy: never stop the pool for it
            log.warning("progress: %s", exc)
            return
        if text:
            log.info("%s", text)


def _start_resource_tracker() -> None:
    """Start multiprocessing's resource tracker (a child that cleans up the Events'
    semaphores) with SIGHUP ignored: it ignores SIGINT and SIGTERM itself but not SIGHUP,
    so a hang-up sent to the pool's process group killed it, and the pool's exit then
    printed a screenful of KeyError tracebacks from its replacement. An ignored signal
    stays ignored across exec."""
    if not hasattr(signal, "SIGHUP"):
        return
    from multiprocessing import resource_tracker
    try:
        old = signal.signal(signal.SIGHUP, signal.SIG_IGN)
    except ValueError:  # not the main thread: signals are not ours to set
        return
    try:
        resource_tracker.ensure_running()
    finally:
        signal.signal(signal.SIGHUP, old)


class Pool:
    def __init__(self, opts: WorkerOptions, n_workers: int,
                 target: Callable[..., None] | None = None) -> None:
        # target(opts, stop, abort, pool_pid) runs in each worker process (tests swap it)
        self.opts, self.n_workers = opts, n_workers
        self.target = target or worker_main
        # Before any worker is spawned: they inherit it, and load numpy's OpenBLAS, which
        # reads it once, before any code of theirs runs (slopetui.queue.blas_threads).
        one_blas_thread()
        self.ctx = mp.get_context("spawn")
        _start_resource_tracker()
        self.stop, self.abort = self.ctx.Event(), self.ctx.Event()
        self.procs: dict[int, BaseProcess] = {}  # sentinel -> process
        self.deaths = DeathWindow(MAX_DEATHS_PER_WORKER * n_workers)
        self.gave_up = False
        self.abort_at: float | None = None

    def _spawn(self) -> None:
        proc = self.ctx.Process(target=self.target,
                                args=(self.opts, self.stop, self.abort, os.getpid()),
                                name=f"slopetui-worker-{len(self.procs)}")
        restore = block_stop_signals()  # the worker unblocks them (block_stop_signals)
        try:
            proc.start()
        finally:
            restore()
        self.procs[proc.sentinel] = proc

    def _act_on(self, signals: SignalPipe) -> None:
        """Turn the signals counted so far into the workers' Events (here, never in a
        handler)."""
        n = signals.poll()
        if n >= 1 and not self.stop.is_set():
            log.info("%s: workers finish the runs they are computing, then exit (again: "
                     "give them back now)", signals.name())
            self.stop.set()
        if n >= 2 and not self.abort.is_set():
            log.info("%s again: workers give their runs back and exit", signals.name())
            self.abort.set()
            self.abort_at = time.monotonic()

    def _reap(self, db: Database, proc: BaseProcess) -> None:
        proc.join()
        wid = worker_id_for(proc.pid or 0, self.opts.host)
        if proc.exitcode == WRITE_REFUSED:  # it said why, in one line
            if not self.gave_up:
                log.error("the store refuses writes (the worker's line above says why): the "
                          "pool stops, its workers give their runs back now; exit status 1")
            self.gave_up = True
            # abort, not only stop: a run whose result cannot be written is not worth the
            # hours it may still take; its lease expires and it goes back to the queue
            self.stop.set()
            if not self.abort.is_set():
                self.abort.set()
                self.abort_at = time.monotonic()
            return
        if proc.exitcode == 0:
            if not (self.stop.is_set() or self.opts.leaves_when_idle):
                log.info("worker %s left (exit status 0: it was sent SIGTERM); not "
                         "replaced, %d workers left", wid, len(self.procs))
            return
        requeued, failed = registry.requeue_worker(
            db, wid, f"worker {wid} died (exit code {proc.exitcode})", self.opts.max_attempts)
        log.error("worker %s died (exit code %s): %d jobs requeued, %d failed", wid,
                  proc.exitcode, requeued, failed)
        if self.stop.is_set():
            return
        if self.deaths.add(time.monotonic()):
            log.error("giving up: more than %d workers died within %g s (see the errors "
                      "above); the pool exits with status 1", self.deaths.limit,
                      self.deaths.window_s)
            self.gave_up = True
            self.stop.set()
            return
        self._spawn()

    def _kill_stuck(self) -> None:
        """After an abort, kill the workers that did not leave within ABORT_GRACE_S."""
        if self.abort_at is None or time.monotonic() - self.abort_at < ABORT_GRACE_S:
            return
        for proc in self.procs.values():
            if proc.is_alive():
                log.warning("worker %s did not stop within %g s: killed",
                            worker_id_for(proc.pid or 0, self.opts.host), ABORT_GRACE_S)
                proc.kill()
        self.abort_at = None

    def _abandon(self) -> None:
        """The pool itself failed (an error of its own, e.g. a write of the store
        refused): its workers give their runs back and exit now, and are killed after
        ABORT_GRACE_S. They must not outlive it: multiprocessing's exit handler waits for
        them, and a pool on a full disk hung that way with its last worker polling."""
        self.stop.set()
        self.abort.set()
        deadline = time.monotonic() + ABORT_GRACE_S
        for proc in self.procs.values():
            proc.join(max(0.0, deadline - time.monotonic()))
            if proc.is_alive():
                proc.kill()
                proc.join()

    def run(self, *, exiting: bool = False) -> int:
        """Run until stopped (or until its workers leave: slopetui.queue.idle_exit).
        Returns the exit status: 0, or 1 if it gave up (see the module docstring).
        ``exiting``: the process exits once the pool has stopped (`slopetui worker`): the
        stop signals stay ignored from then on (stop_signals.SignalPipe.close)."""
        db = open_store(self.opts.db_url)  # migrates a new or old database, under a lock
        damage = integrity_problems(db, quick=True)
        if damage:  # results written into a damaged file could be lost with it
            log.error("the database file %s is damaged (%s): the pool does not start; "
                      "`slopetui db check` lists what is broken", db.path, damage[0])
            return 1
        refused = refuses_writes(db)
        if refused is not None:  # said now, not after a warm-up of up to 20 s for nothing
            log.error("%s: the pool does not start", refused)
            db.dispose()
            return 1
        url = db.url.render_as_string(hide_password=False)
        slots = None if db.is_sqlite else slots_folder(f"{self.opts.host}-{os.getpid()}")
        if slots is not None:  # the pool and its workers share the budget from now on
            self.opts = replace(self.opts, slots_folder=str(slots))
            db.dispose()
            db = self.opts.open_store()
        signals = SignalPipe(STOP_SIGNALS)
        try:
            write_pool_file(url, os.getpid(), self.opts.log_path)
            log.info("pool of %d workers on %s (pid %d)%s", self.n_workers, db.display_url,
                     os.getpid(), f", at most {self.opts.connections} connections at once"
                     if slots is not None else "")
            if pool_warm_up(lambda: signals.poll() > 0) is None:
                log.info("%s during the warm-up: pool stopped before its workers started",
                         signals.name())
                return 0
            for _ in range(self.n_workers):
                self._spawn()
            source = self.opts.progress
            progress = Progress(source(db) if source is not None else lambda: None)
            while self.procs:
                ready = wait([*self.procs, signals.fileno()], timeout=1.0)
                self._act_on(signals)
                for sentinel in ready:
                    if sentinel in self.procs:
                        self._reap(db, self.procs.pop(sentinel))
                self._kill_stuck()
                progress.tick()
                db.idle()  # its slot back to the workers until the next statement
            progress.tick(force=True)  # where the pool left the sweeps
        except BaseException:
            self._abandon()
            raise
        finally:
            signals.close(then_ignore=exiting)
            remove_pool_file(url, os.getpid())
            db.dispose()
            if slots is not None:
                remove_slots_folder(slots)
        log.info("pool stopped%s", " (gave up)" if self.gave_up else "")
        return 1 if self.gave_up else 0


def _stderr_is(path: str | None) -> bool:
    """Is stderr that file (a detached pool writes its stderr into its own log)?"""
    if not path:
        return False
    try:
        a, b = os.fstat(sys.stderr.fileno()), os.stat(path)
    except (OSError, ValueError, AttributeError):
        return False
    return (a.st_dev, a.st_ino) == (b.st_dev, b.st_ino)


def run_pool(opts: WorkerOptions, n_workers: int, *, exiting: bool = False) -> int:
    """Run a pool in this process; its own messages (start, progress, stop, errors) also go
    to stderr, unless stderr is the log file itself (a detached pool). ``exiting``: see
    Pool.run."""
    configure_logging(opts.log_path, echo=not _stderr_is(opts.log_path))
    return Pool(opts, n_workers).run(exiting=exiting)
