"""The kinds of job the queue runs, in the order a worker claims them, and what is done
to every kind at once: heartbeat, requeue, the backlog, the activity ``status`` and
``workers`` print.

The order: a continuation first, then a hysteresis sweep, then a curve in two parameters
(all three are asked for interactively and take one worker for seconds to minutes, while a
sweep's runs keep the others busy), then a batch of runs. It is also the order of the job tables in every
statement that spans several (slopetui.store.jobs.leases: the lock order).

A new kind of job is one module plus its table. It writes:

1. its table: a ``LeasedJob`` model in slopetui.store.models (and its points' model, if
   it saves points) and a migration that creates them;
2. its rows module in slopetui.store.jobs (as hysteresis_sweeps): a ``PointJobs`` over the
   table with the frozen dataclasses its rows are read into, and its finish;
3. its module in slopetui.queue (as hysteresis_jobs): what a job is, built and checked
   from its row, and a ``JobKind`` (slopetui.queue.kinds) with its claim, compute and
   describe, its lease being its rows module's ``lease``;
4. its line in ``KINDS`` below.

The worker, the heartbeat, the requeues, ``status``, ``workers`` and the pool's idle
exit then take it as they take the others.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

from slopetui.queue.branch_jobs import CONTINUATIONS
from slopetui.queue.curve_jobs import CURVES
from slopetui.queue.defaults import LEASE_S, MAX_ATTEMPTS
from slopetui.queue.hysteresis_jobs import HYSTERESIS_SWEEPS
from slopetui.queue.kinds import Activity, JobKind
from slopetui.queue.run_batches import RUNS
from slopetui.store.database import Database
from slopetui.store.jobs import leases
from slopetui.store.jobs.backlog import Backlog, run_backlog

#: Every kind, in claim order (module docstring).
KINDS: tuple[JobKind[Any], ...] = (CONTINUATIONS, HYSTERESIS_SWEEPS, CURVES, RUNS)
_LEASES = tuple(kind.lease for kind in KINDS)


def heartbeat(db: Database, worker_id: str) -> None:
    """Extend the leases of every job the worker holds, of every kind (runs: one, or a
    batch), and mark the worker alive: one transaction."""
    leases.heartbeat(db, _LEASES, worker_id)


def requeue_expired(db: Database, lease_s: float = LEASE_S,
                    max_attempts: int = MAX_ATTEMPTS) -> tuple[int, int]:
    """Jobs of every kind whose lease expired go back to the queue (or fail after
    max_attempts). Returns (requeued, failed)."""
    return leases.requeue_expired(db, _LEASES, lease_s, max_attempts)


def requeue_worker(db: Database, worker_id: str, reason: str,
                   max_attempts: int = MAX_ATTEMPTS) -> tuple[int, int]:
    """The jobs of every kind a worker known to be dead holds go back at once, without
    waiting for the lease, and the worker is marked stopped. Returns (requeued,
    failed)."""
    return leases.requeue_worker(db, _LEASES, worker_id, reason, max_attempts)


def activity(db: Database) -> Iterator[tuple[JobKind[Any], Activity]]:
    """Each kind but the runs (whose progress is their sweeps', slopetui.sweeps.progress,
    and whose worker names its run), with its activity."""
    for kind in KINDS:
        if kind is not RUNS:
            yield kind, kind.describe(db)


def backlog(db: Database) -> Backlog:
    """The queue's backlog, read now: the runs' (with their paused sweeps), and every
    other kind's queued and running jobs."""
    runs = run_backlog(db)
    claimable, running = runs.claimable, runs.running
    for kind in KINDS:
        if kind is not RUNS:  # a run's backlog depends on its sweep's status
            counts = kind.lease.status_counts(db)
            claimable += counts.get("queued", 0)
            running += counts.get("running", 0)
    return Backlog(claimable=claimable, running=running, paused=runs.paused)
