"""What a kind of job is to the queue (``JobKind``), and what a worker hands a kind to
compute one (``Computing``). The kinds themselves, in the order a worker claims them, are
in slopetui.queue.registry; the lease every kind is held under is one implementation,
slopetui.store.jobs.leases.

In the style of procrastinate, whose ``manager.JobManager`` holds a job's statements
(fetch, finish, retry) apart from the worker, which knows no task by name: here the
store's ``Lease`` and rows modules hold the statements, and the worker asks each kind of
the registry in turn for a claim, hands what it got to that kind's compute, and
heartbeats and requeues every kind's lease at once; ``status`` and ``workers`` print each
kind's ``describe``.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable
from dataclasses import dataclass
from typing import Generic, TypeVar

from slopetui.queue.thread_steps import Controls, Runner
from slopetui.store.database import Database
from slopetui.store.jobs.leases import Lease

J = TypeVar("J")


@dataclass(frozen=True)
class Computing:
    """What the worker hands a kind's claim and compute: its store and id, the compute
    thread (``run``: a function run there and waited for, None on an abort), its stop
    sources, and its options (slopetui.queue.worker_process.WorkerOptions)."""

    db: Database
    worker_id: str
    run: Runner
    control: Controls
    max_attempts: int
    #: Runs claimed together, and the memory they may take (MiB).
    batch: int
    memory_mib: int
    #: A step after each batch of runs (slopetui.queue.worker_process.IdleHook).
    idle_hook: Callable[[Database], int] | None = None


@dataclass(frozen=True)
class Activity:
    """A kind's jobs per status, and the job each worker computes (by worker id)."""

    counts: dict[str, int]
    held: dict[str, int]


class JobKind(ABC, Generic[J]):
    """One kind of job: a table of jobs held under the lease (``lease``), and how a
    worker claims, computes and writes one. ``J`` is what a claim hands to compute (a
    run's batch, a continuation, a sweep)."""

    #: The kind's name in the log ("continuation").
    name: str
    #: The word before a job's id in a worker's line of ``status`` and ``workers``
    #: ("branch 5").
    label: str
    #: Its name in ``status`` ("continuations"), and the key of its counts in the JSON
    #: of ``status`` ("continuations").
    plural: str
    key: str
    #: The key of the job each worker computes, in the JSON of ``status``
    #: ("continuation_id").
    id_key: str
    #: The command that shows its jobs, for ``status`` ("slopetui branch").
    shown_by: str
    #: The lease of its table (slopetui.store.jobs.leases): its heartbeat and its requeues.
    lease: Lease

    @abstractmethod
    def claim(self, c: Computing) -> J | None:
        """Lease the next job of this kind to the worker, its stored inputs checked (a row
        that cannot be computed fails at once with the reason, and the next is claimed);
        None when nothing of this kind is claimable."""

    @abstractmethod
    def compute(self, c: Computing, job: J) -> None:
        """Compute the claimed job, writing each result as soon as it is known, guarded by
        the lease (a run's result, a saved point, the finish); a stop gives back what was
        not started, an abort gives back everything held, an error is recorded on the job
        (retried up to max_attempts)."""

    @abstractmethod
    def describe(self, db: Database) -> Activity:
        """Its jobs per status, and the one each worker computes (by worker id)."""
