"""Runs as a kind of job (``RUNS``): a worker claims a batch of runs, computes it, and
writes each result as soon as it is known.

A batch is up to ``batch`` queued runs with the same solver settings and tau (the batched
kernels' lanes share tau: store.runs.claims.claim_batch), cut to the worker's memory budget
(slopetui.queue.batch_memory). Euler and RK4 batches (BATCHED_METHODS) go through the
batched kernels (core.batch) in one call, which reports nothing until every lane is done
(core.run_batch has no per-lane callback), so their results are written when it returns,
and every run of the batch, being in the kernel, is charged an attempt. A run of another
method (stiff) or history (not the constant one) is claimed alone, charged its attempt
when it starts and written when it ends (jobs.begin, jobs.complete): a killed worker
loses only the run it was computing. What a run is, and the queue's policy for it, are
slopetui.queue.jobs.

Stop: finish the run in the kernel, give the runs not started back. Abort: give every
held run back now (slopetui.queue.worker_process).
"""

from __future__ import annotations

import logging
import traceback
from concurrent.futures import Future
from functools import partial
from typing import TYPE_CHECKING, Any

from core.methods import METHOD_TABLE
from slopetui.queue import jobs
from slopetui.queue.batch_memory import MIB, fitting
from slopetui.queue.kinds import Activity, Computing, JobKind
from slopetui.store.database import Database
from slopetui.store.runs import claims

if TYPE_CHECKING:  # numpy: loaded by the kernels, after the worker has started
    from core.history import CarriedState

log = logging.getLogger("slopetui.worker")

#: Methods computed with the batched kernels (core.batch; core.methods says which), whose
#: lanes share tau; a run of another method (stiff) is claimed alone and computed by the
#: single-run kernel.
BATCHED_METHODS = frozenset(m.name for m in METHOD_TABLE if m.batched)

Records = list[dict[str, Any]]


def _compute_one(job: jobs.Job, carried: CarriedState | None = None) -> Records:
    # core loads numpy and the kernels: not for `status`, which reads the registry
    from core.point import run_point
    return [run_point(job.params, job.settings, carried).as_record()]


def _compute_together(batch: list[jobs.Job]) -> Records:
    # core.run_batch has no per-lane callback (one numba call integrates every lane), so
    # its results are all known, and written, when it returns.
    from core.point import run_batch
    return [result.as_record() for result in run_batch([job.params for job in batch],
                                                       batch[0].settings)]


def _within_memory(db: Database, wid: str, batch: list[jobs.Job], memory_mib: int) -> list[jobs.Job]:
    """The leading runs of the batch that fit the memory budget; the others go back to the
    queue unstarted (slopetui.queue.batch_memory). Only a batch for the batched kernels,
    which hold every lane's buffers at once: a batch computed run by run (_one_by_one)
    frees each run's buffers before the next."""
    if len(batch) < 2 or batch[0].settings.method not in BATCHED_METHODS:
        return batch
    keep = fitting(batch, memory_mib * MIB)
    if keep < len(batch):
        log.info("batch cut to %d of %d runs: the memory budget is %d MiB (worker --memory)",
                 keep, len(batch), memory_mib)
        _give_back(db, wid, batch[keep:])
    return batch[:keep]


def _give_back(db: Database, wid: str, held: list[jobs.Job]) -> None:
    """Release held runs: a started run's attempt is returned, an unstarted run was never
    charged."""
    unstarted = 0
    for job in held:
        released = jobs.release(db, job, wid)
        if job.started:
            log.info("run %d given back to the queue (shutdown)%s", job.run_id,
                     "" if released else "; its lease had already been taken over")
        else:
            unstarted += released
    if unstarted:
        log.info("%d claimed runs not started given back to the queue", unstarted)


def _write(db: Database, wid: str, batch: list[jobs.Job], future: Future[Records],
           max_attempts: int, size: int) -> None:
    """Write the results of a finished computation (guarded by the lease), or its error."""
    error = future.exception()
    if error is None:
        for job, record in zip(batch, future.result(), strict=True):
            if jobs.complete(db, job, wid, record):
                log.info("run %d done: %s in %.2f s (attempt %d, batch of %d)", job.run_id,
                         record["regime"], record["runtime_s"], job.attempts, size)
            else:
                log.warning("run %d finished after its lease was lost; result discarded",
                            job.run_id)
        return
    text = "".join(traceback.format_exception(error)).strip()
    for job in batch:
        status = jobs.fail(db, job, wid, text, max_attempts)
        log.error("run %d raised (attempt %d, now %s): %s", job.run_id, job.attempts,
                  status, error)


def _from_cache(db: Database, wid: str, job: jobs.Job) -> bool:
    """Complete the run if an identical finished run already answers it."""
    hit = jobs.cached_result(db, job)
    if hit is None:
        return False
    jobs.complete(db, job, wid, hit[1], cached_from=hit[0])
    log.info("run %d done (cached from run %d)", job.run_id, hit[0])
    return True


def _one_by_one(c: Computing, batch: list[jobs.Job]) -> None:
    """Each run: charge it, compute it, write it. A stop between two runs gives the runs
    not started back; an abort also gives back the run in the kernel."""
    db, wid = c.db, c.worker_id
    for i, job in enumerate(batch):
        if c.control.stopping():
            _give_back(db, wid, batch[i:])
            return
        if _from_cache(db, wid, job):
            continue
        started = jobs.begin(db, [job], wid)
        if not started:
            log.warning("run %d: lease lost before it started; skipped", job.run_id)
            continue
        # the final state its history names was read and checked at the claim (jobs)
        future = c.run(partial(_compute_one, started[0], started[0].carried))
        if future is None:
            _give_back(db, wid, started + batch[i + 1:])
            return
        _write(db, wid, started, future, c.max_attempts, len(batch))


def _together(c: Computing, batch: list[jobs.Job]) -> None:
    """The whole batch in one call of the batched kernel: every run of it is in the kernel,
    so every one is charged; an abort gives them all back."""
    db, wid = c.db, c.worker_id
    batch = [job for job in batch if not _from_cache(db, wid, job)]
    if c.control.stopping():
        _give_back(db, wid, batch)
        return
    started = jobs.begin(db, batch, wid)
    if not started:
        return
    future = c.run(partial(_compute_together, started))
    if future is None:
        _give_back(db, wid, started)
        return
    _write(db, wid, started, future, c.max_attempts, len(started))


class Runs(JobKind[list[jobs.Job]]):
    """Runs of sweeps, claimed and computed in batches (module docstring)."""

    name = label = "run"
    plural = key = "runs"
    id_key = "run_id"
    shown_by = "slopetui status"
    lease = claims.lease

    def claim(self, c: Computing) -> list[jobs.Job] | None:
        batch = _within_memory(c.db, c.worker_id,
                               jobs.claim_batch(c.db, c.worker_id, c.batch, BATCHED_METHODS),
                               c.memory_mib)
        return batch or None

    def compute(self, c: Computing, job: list[jobs.Job]) -> None:
        # a batch of several holds runs of the constant history only (claims.claim_batch
        # claims any other alone): the batched kernels know no other
        if len(job) > 1 and job[0].settings.method in BATCHED_METHODS:
            _together(c, job)
        else:
            _one_by_one(c, job)
        # e.g. an adaptive sweep whose level is complete queues its next level
        if not c.control.aborting() and c.idle_hook is not None:
            c.idle_hook(c.db)

    def describe(self, db: Database) -> Activity:
        return Activity(self.lease.status_counts(db), self.lease.held(db))


RUNS = Runs()
