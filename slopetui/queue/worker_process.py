"""One worker process of the pool: claim a job, compute it, write each result as soon as
it is known, repeat.

Each round asks the kinds of job of slopetui.queue.registry in turn (continuations,
hysteresis sweeps, then a batch of runs: slopetui.queue.run_batches) and computes the
first it gets with that kind's compute. The signal plumbing is in
slopetui.queue.stop_signals, the warm-up in slopetui.queue.warm_up. The computation runs
in a thread (the numba kernels release the GIL), so the main thread stays free to notice
a shutdown and, while it waits, sends the heartbeat that extends the leases of every job
the worker holds (Heartbeat).

Connections. The main thread is the only one that uses the store, and it closes its
connection whenever it waits (a computation, a sleep: Database.idle). On a server
database the pool's processes share a budget of connections (WorkerOptions.connections,
slopetui.ops.connection_slots): the pool holds at most that many, whatever its size.

Shutdown. The main loop reads three sources, and nothing else acts on them:

* the pool's ``stop`` and ``abort`` Events (the pool sets them from its main loop). They
  are only read (is_set), never waited on: a process sleeping in Event.wait() makes the
  pool's Event.set() wait until it wakes (see slopetui.queue.pool);
* SIGTERM sent to this process (systemd stops the whole control group; the kernel sends
  it when the pool dies, PR_SET_PDEATHSIG). The handler does nothing: CPython's C-level
  handler writes a byte to the wakeup pipe (signal.set_wakeup_fd), and the loop counts
  the bytes. A handler must not touch a multiprocessing Event or lock: it runs in the
  main thread, possibly while that thread is inside the same Event's wait, and deadlocks;
* the pool's pid against getppid(): a worker whose pool is gone stops.

Stop (first SIGTERM, ``stop``, pool gone): finish the run in the kernel, give the runs not
started back, exit 0. Abort (second SIGTERM, ``abort``): give every held run back now and
exit 0 at once; not for an orphan, whose SIGTERMs are its pool's death (Control.aborting).
SIGINT and SIGHUP are ignored: Ctrl-C and a hang-up reach every process of
the terminal's group, and the pool decides for all.
"""

from __future__ import annotations

import logging
import math
import os
import select
import signal
import socket
import time
from collections.abc import Callable
from concurrent.futures import Future, ThreadPoolExecutor
from concurrent.futures import wait as wait_futures
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from slopetui.ops.connection_slots import DEFAULT_CONNECTIONS, ConnectionSlots
from slopetui.queue import defaults, jobs, registry
from slopetui.queue.idle_exit import IdleExit, Owner
from slopetui.queue.kinds import Computing
from slopetui.queue.local_pool import open_private_log, process_state
from slopetui.queue.priority import lower_priority
from slopetui.queue.stop_signals import STOP_SIGNALS, SignalPipe, die_with_parent
from slopetui.queue.warm_up import watched_warm_up
from slopetui.store.database import Database
from slopetui.store.workers import register_worker, unregister_worker
from slopetui.store.write_checks import write_refusal

log = logging.getLogger("slopetui.worker")

#: How often the main thread looks at the stop sources while it waits (s).
TICK_S = 0.2
#: A worker's exit status when the store refused a write (read-only, full disk, no
#: privilege: slopetui.store.write_checks): it has said why in one line, and the pool
#: stops rather than start workers that would meet the same refusal. sysexits.h's
#: EX_IOERR: no crash exits with it (a traceback exits 1, a signal 128+n or -n).
WRITE_REFUSED = 74


#: A step a worker takes after each batch (unless it is aborting) and whenever it finds
#: nothing to claim; returns how much work it queued (0: none, the worker may then sleep).
#: The faces pass slopetui.sweeps.adaptive.advance_all (an adaptive sweep whose level is
#: complete queues its next level): the queue knows no sweeps. It travels to the spawned
#: workers inside WorkerOptions, so it must pickle by reference: a module-level function.
IdleHook = Callable[[Database], int]
#: Where the pool's progress line comes from (the pool's own process only): called once
#: with the pool's Database, it returns the function that gives the line ("12/240 runs
#: done, ...") or None when nothing changed. The faces pass
#: slopetui.sweeps.progress.PoolProgress; a class or module-level function, as IdleHook.
ProgressSource = Callable[[Database], Callable[[], str | None]]


@dataclass(frozen=True)
class WorkerOptions:
    """Settings shared by the pool's workers (times in seconds)."""

    db_url: str
    log_path: str | None = None
    poll_s: float = 1.0
    heartbeat_s: float = defaults.HEARTBEAT_S
    lease_s: float = defaults.LEASE_S
    max_attempts: int = defaults.MAX_ATTEMPTS
    #: Leave once nothing is queued or running; with queued runs only in paused sweeps,
    #: once nothing has been claimable for idle_grace_s (slopetui.queue.idle_exit).
    exit_when_idle: bool = False
    #: How long nothing may be claimable before a worker that leaves on its own leaves
    #: while something may still come back (slopetui.queue.idle_exit).
    idle_grace_s: float = defaults.IDLE_GRACE_S
    #: The process the pool works for (the application that started it): once it has
    #: quit, the workers leave when the store has been idle for idle_grace_s.
    owner: Owner | None = None
    #: Runs claimed and computed together (see the module docstring); 1: one at a time.
    batch: int = defaults.DEFAULT_BATCH
    #: The memory the runs of a batch may take together (MiB; slopetui.queue.batch_memory):
    #: a batch of long windows is cut to fit, the rest given back to the queue.
    memory_mib: int = defaults.MEMORY_MIB
    #: See IdleHook; None: no step.
    idle_hook: IdleHook | None = None
    #: See ProgressSource; None: the pool logs no progress line.
    progress: ProgressSource | None = None
    #: The name the workers' ids carry (``host:pid``); None: the host's name. Distinct
    #: names let several pools on one machine stand for several hosts (tests).
    host_id: str | None = None
    #: Connections the pool's processes may hold at once on a server database (see the
    #: module docstring); SQLite has no budget.
    connections: int = DEFAULT_CONNECTIONS
    #: The folder of the pool's connection slots, made by the pool (None: no budget).
    slots_folder: str | None = None

    def __post_init__(self) -> None:
        # `slopetui worker` checks its options with friendlier words; this guards the other
        # callers: an infinite heartbeat would kill the heartbeat thread (Event.wait(inf)
        # raises OverflowError), and leases would then expire under a live worker.
        for name in ("poll_s", "heartbeat_s", "lease_s"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ValueError(f"WorkerOptions.{name} must be finite and > 0, got {value}")
        if not (math.isfinite(self.idle_grace_s) and self.idle_grace_s >= 0):
            raise ValueError(f"WorkerOptions.idle_grace_s must be finite and >= 0, got "
                             f"{self.idle_grace_s}")
        if self.lease_s < 2 * self.heartbeat_s:
            raise ValueError("WorkerOptions.lease_s must be >= 2 x heartbeat_s")
        if min(self.max_attempts, self.batch, self.connections, self.memory_mib) < 1:
            raise ValueError("WorkerOptions.max_attempts, batch, connections and memory_mib "
                             "must be >= 1")

    @property
    def leaves_when_idle(self) -> bool:
        """Do the workers leave on their own (exit status 0) once there is nothing to do?"""
        return self.exit_when_idle or self.owner is not None

    @property
    def host(self) -> str:
        return self.host_id or socket.gethostname()

    def open_store(self) -> Database:
        """The store, under the pool's connection budget if it has one (not migrated:
        the pool migrated it before it spawned anyone)."""
        slots = (ConnectionSlots(Path(self.slots_folder), self.connections)
                 if self.slots_folder else None)
        return Database(self.db_url, slots=slots)


def worker_id_for(pid: int, host: str | None = None) -> str:
    return f"{host or socket.gethostname()}:{pid}"


def configure_logging(log_path: str | None, echo: bool = False) -> None:
    """Log to the file (every process of the pool appends to it; created 0600: it holds
    runs' errors and tracebacks); ``echo`` also to stderr."""
    handlers: list[logging.Handler] = []
    if log_path:
        os.close(open_private_log(Path(log_path)))  # FileHandler would create it 0644
        handlers.append(logging.FileHandler(log_path, encoding="utf-8"))
    if echo or not log_path:
        handlers.append(logging.StreamHandler())
    root = logging.getLogger("slopetui")
    root.handlers[:] = handlers
    for handler in handlers:
        handler.setFormatter(logging.Formatter(
            "%(asctime)s %(process)d %(levelname)s %(message)s"))
    root.setLevel(logging.INFO)


class Control:
    """What the worker should do now, read from the stop sources of the module docstring.
    Only the main loop calls it; nothing here runs in a signal handler."""

    def __init__(self, signals: SignalPipe, stop: Any, abort: Any, pool_pid: int) -> None:
        self.signals, self.stop, self.abort, self.pool_pid = signals, stop, abort, pool_pid
        self._said: str | None = None
        #: Called while the main thread waits (at most every TICK_S): the Heartbeat.
        self.tick: Callable[[], None] = lambda: None

    def orphaned(self) -> bool:
        """The pool is gone, or going: this worker was re-parented, or the pool's main
        thread has exited (a zombie leader while its other threads die)."""
        return (os.getppid() != self.pool_pid
                or process_state(self.pool_pid) in ("Z", "X"))

    def aborting(self) -> bool:
        # A pool killed with kill -9 sends PR_SET_PDEATHSIG's SIGTERM once per thread of
        # it that the worker is re-parented through on the way to init (two or more): those
        # SIGTERMs are the pool's death, a stop, not a second SIGTERM asking for an abort.
        return self.abort.is_set() or (self.signals.poll() >= 2 and not self.orphaned())

    def stopping(self) -> bool:
        return (self.aborting() or self.signals.count >= 1 or self.stop.is_set()
                or self.orphaned())

    def reason(self) -> str:
        if self.abort.is_set():
            return "the pool asks for an immediate stop: giving the held runs back now"
        if self.orphaned():  # its SIGTERMs (PR_SET_PDEATHSIG) say less
            return f"the pool (pid {self.pool_pid}) is gone: finishing the run in " \
                   "progress, then exiting"
        if self.signals.count >= 2:
            return "SIGTERM again: giving the held runs back now"
        if self.signals.count:
            return "SIGTERM: finishing the run in progress, then exiting"
        return "the pool asks for a stop: finishing the run in progress, then exiting"

    def say(self, wid: str) -> None:
        """Log why the worker stops (once per reason)."""
        reason = self.reason()
        if reason != self._said:
            log.info("worker %s: %s", wid, reason)
            self._said = reason

    def sleep(self, seconds: float) -> None:
        """Wait up to ``seconds``; a signal wakes it at once, a stop within TICK_S."""
        deadline = time.monotonic() + seconds
        while not self.stopping():
            self.tick()
            left = deadline - time.monotonic()
            if left <= 0:
                return
            select.select([self.signals.fileno()], [], [], min(left, TICK_S))


class Heartbeat:
    """Extends the leases of the held jobs and requeues those of dead workers, every
    heartbeat_s, from the main thread while it waits (Control.tick), and closes the
    connection until the next statement (Database.idle). A main thread that is stuck
    sends none, and its jobs go to other workers when their leases expire."""

    def __init__(self, db: Database, worker_id: str, opts: WorkerOptions) -> None:
        self.db, self.worker_id, self.opts = db, worker_id, opts
        self.next_at = time.monotonic() + opts.heartbeat_s

    def __call__(self) -> None:
        now = time.monotonic()
        if now >= self.next_at:
            self.next_at = now + self.opts.heartbeat_s
            try:
                registry.heartbeat(self.db, self.worker_id)
                requeued, failed = registry.requeue_expired(self.db, self.opts.lease_s,
                                                        self.opts.max_attempts)
                if requeued or failed:
                    log.warning("expired leases: %d jobs requeued, %d failed", requeued, failed)
            except Exception as exc:  # a busy or briefly unreachable database: try again later
                refused = write_refusal(self.db, exc)
                if refused is None:
                    log.exception("heartbeat failed")
                else:  # one line: the write of the result will say it again, and leave
                    log.warning("heartbeat failed: %s", refused)
        self.db.idle()


def _wait(future: Future[Any], control: Control) -> bool:
    """Wait for the computation; False if an abort came first (it is left running)."""
    control.tick()  # no connection held while it computes (Heartbeat)
    while not wait_futures([future], timeout=TICK_S).done:
        if control.aborting():
            return False
        control.tick()
    return True


def _run(fn: Callable[[], Any], executor: ThreadPoolExecutor, control: Control
         ) -> Future[Any] | None:
    """``fn`` in the compute thread, waited for; None if an abort came first."""
    future = executor.submit(fn)
    return future if _wait(future, control) else None


def _claim_and_compute(c: Computing) -> bool:
    """Claim a job of the first kind that has one (slopetui.queue.registry's order) and
    compute it; False if no kind had anything to claim."""
    for kind in registry.KINDS:
        job = kind.claim(c)
        if job is not None:
            kind.compute(c, job)
            return True
    return False


def _unregister(db: Database, wid: str) -> None:
    """Mark the worker stopped; a store that refuses the write has had its line."""
    try:
        unregister_worker(db, wid)
    except Exception as exc:
        if write_refusal(db, exc) is None:
            raise


def worker_main(opts: WorkerOptions, stop: Any, abort: Any, pool_pid: int) -> None:
    """Entry point of a spawned worker process (stop and abort are multiprocessing Events,
    set by the pool's main loop; pool_pid is the pool, given rather than read with
    getppid(), which would already say 1 if the pool died while this process started)."""
    # First, before anything slow: die with the pool, and catch a pool already gone.
    die_with_parent()
    if os.getppid() != pool_pid:
        os._exit(0)
    lower_priority(defaults.WORKER_NICE)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGHUP, signal.SIG_IGN)
    signals = SignalPipe([signal.SIGTERM])
    if hasattr(signal, "pthread_sigmask"):  # the pool spawned us with them blocked
        signal.pthread_sigmask(signal.SIG_UNBLOCK, STOP_SIGNALS)
    control = Control(signals, stop, abort, pool_pid)
    configure_logging(opts.log_path)
    wid = worker_id_for(os.getpid(), opts.host)
    jobs.engine_digest()  # the engine's sources as this worker loads them (jobs.complete)
    # Every kernel now, not lazily at a claim's first call: a lazy load saves little CPU
    # (0.2-0.3 s) once the worker claims, and counts in its first runs' stored runtime_s
    # (measured: slopetui.queue.warm_up's docstring).
    if watched_warm_up(control.stopping, announce=False) is None:
        control.say(wid)  # nothing claimed, nothing registered: just leave
        logging.shutdown()
        os._exit(0)
    db = opts.open_store()
    executor = ThreadPoolExecutor(max_workers=1, thread_name_prefix="compute")
    leaving = IdleExit(opts.exit_when_idle, opts.idle_grace_s, opts.owner)
    status = 0
    try:
        register_worker(db, wid, opts.host, os.getpid())
        control.tick = Heartbeat(db, wid, opts)
        log.info("worker %s started", wid)
        computing = Computing(db, wid, lambda fn: _run(fn, executor, control), control,
                              opts.max_attempts, opts.batch, opts.memory_mib, opts.idle_hook)
        while not control.stopping():
            leaving.new_round()
            if _claim_and_compute(computing):
                continue
            # e.g. an adaptive sweep whose level is complete queues its next level
            if opts.idle_hook is not None and opts.idle_hook(db):
                continue
            reason = leaving.reason_to_leave(lambda: registry.backlog(db))
            if reason is not None:
                log.info("worker %s: leaving: %s", wid, reason)
                break
            control.sleep(opts.poll_s)
        if control.stopping():
            control.say(wid)
    except Exception as exc:
        refused = write_refusal(db, exc)
        if refused is None:
            raise
        # one line, no traceback: nothing can be written until someone fixes the store
        log.error("worker %s leaves: %s; the runs it holds go back to the queue when "
                  "their leases expire", wid, refused)
        status = WRITE_REFUSED
    finally:
        _unregister(db, wid)
        log.info("worker %s stopped", wid)
    # os._exit, not a return: the interpreter's finalisation puts SIGTERM's default action
    # back, and a late SIGTERM (the second of a stop) would then kill the worker with -15,
    # which the pool must count as a death. On an abort, a computation may also still run
    # in the thread: it is not waited for.
    executor.shutdown(wait=not control.aborting() and status == 0)
    db.dispose()
    logging.shutdown()
    os._exit(status)
