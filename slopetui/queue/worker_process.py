"""One worker process of the pool: claim a batch of runs, compute it, write the results,
repeat.

A batch is up to ``batch`` queued runs with the same solver settings, computed together by
the batched Euler kernel (core.batch: ~2x the single kernel's throughput; see
BATCHED_METHODS for RK4); ``batch = 1`` uses the single-run kernels. The computation runs in a thread of this process (the numba kernels
release the GIL), so the main thread stays free to notice a shutdown; a heartbeat thread
extends the leases of every run of the batch.
Shutdown: the pool sets ``stop`` (finish the running job, then exit) or ``abort`` (give
the running job back to the queue now, then exit). SIGTERM sent to this process directly
(systemd stops the whole control group) acts as ``stop``, a second SIGTERM as ``abort``.
"""

from __future__ import annotations

import logging
import os
import signal
import socket
import threading
import traceback
from concurrent.futures import Future, ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any

from sqlalchemy import func, select

from slopetui.queue import jobs
from slopetui.store.database import Database
from slopetui.store.db_time import db_now
from slopetui.store.models import Run, Sweep, Worker
from slopetui.sweeps import adaptive

log = logging.getLogger("slopetui.worker")


@dataclass(frozen=True)
class WorkerOptions:
    """Settings shared by the pool's workers (times in seconds)."""

    db_url: str
    log_path: str | None = None
    poll_s: float = 1.0
    heartbeat_s: float = jobs.HEARTBEAT_S
    lease_s: float = jobs.LEASE_S
    max_attempts: int = jobs.MAX_ATTEMPTS
    exit_when_idle: bool = False
    #: Runs claimed and computed together (see the module docstring); 1: one at a time.
    batch: int = 32


def worker_id_for(pid: int) -> str:
    return f"{socket.gethostname()}:{pid}"


def configure_logging(log_path: str | None, echo: bool = False) -> None:
    """Log to the file (every process of the pool appends to it); ``echo`` also to stderr."""
    handlers: list[logging.Handler] = []
    if log_path:
        handlers.append(logging.FileHandler(log_path, encoding="utf-8"))
    if echo or not log_path:
        handlers.append(logging.StreamHandler())
    root = logging.getLogger("slopetui")
    root.handlers[:] = handlers
    for handler in handlers:
        handler.setFormatter(logging.Formatter(
            "%(asctime)s %(process)d %(levelname)s %(message)s"))
    root.setLevel(logging.INFO)


def warm_up() -> None:
    """Compile (or load from numba's cache) every kernel a run can use, with a short run
    of each method, so the first real job does not pay for compilation."""
    from core import Params, SolverSettings, run_batch, run_point
    for method in ("euler", "rk4"):
        settings = SolverSettings(method=method, t_end=20.0, window=10.0)
        run_point(Params(tau=1.0), settings)
        run_batch([Params(tau=1.0), Params(tau=2.0)], settings)


def _register(db: Database, worker_id: str) -> None:
    with db.transaction() as s:
        worker = s.get(Worker, worker_id)
        if worker is None:
            s.add(Worker(id=worker_id, host=socket.gethostname(), pid=os.getpid()))
        else:  # a pid reused on the same host
            worker.stopped_at, worker.run_id, worker.jobs_done = None, None, 0
            worker.started_at = worker.heartbeat_at = db_now()


def _unregister(db: Database, worker_id: str) -> None:
    with db.transaction() as s:
        worker = s.get(Worker, worker_id)
        if worker is not None:
            worker.stopped_at, worker.run_id = db_now(), None


def queue_drained(db: Database) -> bool:
    """Nothing left that a worker could still have to do: no queued run of an active
    sweep and no running run (a running run may come back if its worker dies)."""
    with db.sessions() as s:
        waiting = s.scalar(select(func.count()).select_from(Run).join(Sweep)
                           .where(Run.status == "queued", Sweep.status == "active"))
        running = s.scalar(select(func.count()).select_from(Run)
                           .where(Run.status == "running"))
    return waiting == 0 and running == 0


class _Heartbeat(threading.Thread):
    """Extends the lease of the current run, and requeues the runs of dead workers."""

    def __init__(self, db: Database, worker_id: str, opts: WorkerOptions) -> None:
        super().__init__(name="heartbeat", daemon=True)
        self.db, self.worker_id, self.opts = db, worker_id, opts
        self.halt = threading.Event()

    def run(self) -> None:
        while not self.halt.wait(self.opts.heartbeat_s):
            try:
                jobs.heartbeat(self.db, self.worker_id)
                requeued, failed = jobs.requeue_expired(self.db, self.opts.lease_s,
                                                        self.opts.max_attempts)
                if requeued or failed:
                    log.warning("expired leases: %d runs requeued, %d failed", requeued, failed)
            except Exception:  # a busy or briefly unreachable database: try again later
                log.exception("heartbeat failed")


#: Methods computed with the batched kernels. RK4's batched kernel is not vectorised by LLVM
#: yet and runs at ~0.6x the single kernel's speed (benchmarks/bench_kernels.py), so RK4
#: batches are computed run by run.
BATCHED_METHODS = frozenset({"euler"})


def _compute(batch: list[jobs.Job]) -> list[dict[str, Any]]:
    from core import run_batch, run_point
    settings = batch[0].settings
    if len(batch) == 1 or settings.method not in BATCHED_METHODS:
        return [run_point(job.params, job.settings).as_record() for job in batch]
    return [result.as_record() for result in run_batch([job.params for job in batch],
                                                       settings)]


def _wait(future: Future[list[dict[str, Any]]], abort: Any) -> bool:
    """Wait for the computation; False if abort was set first."""
    while True:
        try:
            future.result(timeout=0.2)
            return True
        except TimeoutError:
            if abort.is_set():
                return False
        except Exception:  # the computation raised: the caller reads it from the future
            return True


def _serve_from_cache(db: Database, wid: str, batch: list[jobs.Job]) -> list[jobs.Job]:
    """Complete the runs an identical finished run already answers; return the others."""
    left = []
    for job in batch:
        hit = jobs.cached_result(db, job)
        if hit is None:
            left.append(job)
        else:
            jobs.complete(db, job, wid, hit[1], cached_from=hit[0])
            log.info("run %d done (cached from run %d)", job.run_id, hit[0])
    return left


def _process(db: Database, wid: str, batch: list[jobs.Job], pool: ThreadPoolExecutor,
             abort: Any, opts: WorkerOptions) -> bool:
    """Run one claimed batch to its end; False if it was given back on abort."""
    batch = _serve_from_cache(db, wid, batch)
    if not batch:
        return True
    future = pool.submit(_compute, batch)
    if not _wait(future, abort):
        for job in batch:
            released = jobs.release(db, job, wid)
            log.info("run %d given back to the queue (shutdown)%s", job.run_id,
                     "" if released else "; its lease had already been taken over")
        return False
    error = future.exception()
    if error is None:
        for job, record in zip(batch, future.result(), strict=True):
            if jobs.complete(db, job, wid, record):
                log.info("run %d done: %s in %.2f s (attempt %d, batch of %d)", job.run_id,
                         record["regime"], record["runtime_s"], job.attempts, len(batch))
            else:
                log.warning("run %d finished after its lease was lost; result discarded",
                            job.run_id)
    else:
        text = "".join(traceback.format_exception(error)).strip()
        for job in batch:
            status = jobs.fail(db, job, wid, text, opts.max_attempts)
            log.error("run %d raised (attempt %d, now %s): %s", job.run_id, job.attempts,
                      status, error)
    return True


def worker_main(opts: WorkerOptions, stop: Any, abort: Any) -> None:
    """Entry point of a spawned worker process (stop and abort are multiprocessing Events)."""
    configure_logging(opts.log_path)
    # Ctrl-C reaches every process of the terminal's group; the pool decides for all.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGHUP, signal.SIG_IGN)

    def on_term(_sig: int, _frame: Any) -> None:
        (abort if stop.is_set() else stop).set()
    signal.signal(signal.SIGTERM, on_term)

    wid = worker_id_for(os.getpid())
    db = Database(opts.db_url, upgrade=False)  # the pool migrated it before spawning us
    warm_up()
    _register(db, wid)
    hb = _Heartbeat(db, wid, opts)
    hb.start()
    log.info("worker %s started", wid)
    parent = os.getppid()
    with ThreadPoolExecutor(max_workers=1, thread_name_prefix="compute") as pool:
        try:
            while not stop.is_set():
                if os.getppid() != parent:  # the pool was killed: do not linger as orphans
                    log.warning("the pool process is gone; worker %s exits", wid)
                    break
                batch = jobs.claim_batch(db, wid, opts.batch)
                if not batch:
                    # an adaptive sweep whose level is complete queues its next level
                    if adaptive.advance_all(db):
                        continue
                    if opts.exit_when_idle and queue_drained(db):
                        break
                    stop.wait(opts.poll_s)
                elif not _process(db, wid, batch, pool, abort, opts):
                    break
                else:
                    adaptive.advance_all(db)
        finally:
            hb.halt.set()
            _unregister(db, wid)
            log.info("worker %s stopped", wid)
        if abort.is_set():
            # A computation may still run in the thread: do not wait for it.
            logging.shutdown()
            os._exit(0)
