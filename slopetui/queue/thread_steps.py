"""The steps of a job computed point by point (continuations: slopetui.queue.branch_jobs,
hysteresis sweeps: slopetui.queue.hysteresis_jobs), each run in the worker's compute
thread while the worker's main thread keeps its heartbeat and watches for stops.

The policy both jobs share, held here once: a step is timed in CPU seconds of the thread
that ran it; an abort (the step did not come back) gives the job back to the queue at once
with its attempt given back, leaving the step unsaved; a stop asked between two steps gives
it back the same way; an error in a step is recorded on the job, which is retried up to
max_attempts unless the error is an answer (nothing to compute), which fails it at once.
"""

from __future__ import annotations

import logging
import time
import traceback
from collections.abc import Callable
from concurrent.futures import Future
from dataclasses import dataclass
from typing import Any, Protocol, TypeVar

from slopetui.store.database import Database

log = logging.getLogger("slopetui.worker")

T = TypeVar("T")
#: Runs a function in the worker's compute thread and waits for it: its Future once done,
#: None when an abort came first (the function is left running).
Runner = Callable[[Callable[[], Any]], "Future[Any] | None"]


class Stops(Protocol):
    def stopping(self) -> bool: ...


class Controls(Stops, Protocol):
    """The worker's stop sources (slopetui.queue.worker_process.Control): a stop, asked
    between two steps; an abort, which gives back at once what is held."""

    def aborting(self) -> bool: ...


class LeaseRows(Protocol):
    """The statements on a held job a step's outcome needs (slopetui.store.jobs.continuations,
    hysteresis_sweeps): record its error, give it back."""

    def fail(self, db: Database, job_id: int, worker_id: str, error: str, /, *,
             give_up: bool) -> bool: ...

    def release(self, db: Database, job_id: int, worker_id: str, /) -> bool: ...


def timed(fn: Callable[[], T]) -> Callable[[], tuple[T, float]]:
    """``fn`` returning also the CPU time its thread spent on it (s)."""
    def run() -> tuple[T, float]:
        t0 = time.thread_time()
        out = fn()
        return out, time.thread_time() - t0
    return run


def no_answer(_error: BaseException) -> str | None:
    """Every error is worth a retry (the default of ``HeldJob.answer``)."""
    return None


@dataclass(frozen=True)
class HeldJob:
    """A job the worker holds while it computes it step by step: ``what`` names its kind
    in the log ("continuation"), ``rows`` records on it what a step came to, and
    ``answer`` tells an error that is an answer (the text recorded, no retry) from one
    worth a retry (None)."""

    db: Database
    wid: str
    id: int
    attempts: int
    what: str
    rows: LeaseRows
    run: Runner
    control: Stops
    max_attempts: int
    answer: Callable[[BaseException], str | None] = no_answer

    def step(self, fn: Callable[[], T]) -> tuple[T, float] | None:
        """Run ``fn`` in the compute thread: its value and the CPU time it took (s). None
        when it did not come back (an abort) or raised: the job was given back or its
        error recorded, and the caller returns."""
        future = self.run(timed(fn))
        if future is None:
            self.give_back("abort")
            return None
        if (error := future.exception()) is not None:
            self.fail(error)
            return None
        out: tuple[T, float] = future.result()
        return out

    def stopped(self) -> bool:
        """Whether a stop was asked (checked between two steps); if so the job was given
        back, and the caller returns."""
        if not self.control.stopping():
            return False
        self.give_back("shutdown")
        return True

    def fail(self, error: BaseException) -> None:
        """Record a step's error: failed for good if it is an answer or the attempts are
        spent, else back to the queue."""
        answer = self.answer(error)
        give_up = answer is not None or self.attempts >= self.max_attempts
        text = answer if answer is not None else "".join(traceback.format_exception(error)).strip()
        if self.rows.fail(self.db, self.id, self.wid, text, give_up=give_up):
            log.error("%s %d %s: %s", self.what, self.id,
                      "failed" if give_up else "raised, back to the queue", error)

    def give_back(self, why: str) -> None:
        """Give the job back to the queue (its attempt given back): a stop or an abort."""
        released = self.rows.release(self.db, self.id, self.wid)
        log.info("%s %d given back to the queue (%s)%s", self.what, self.id, why,
                 "" if released else "; its lease had already been taken over")
