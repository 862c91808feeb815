"""The writes of a sweep's rows: a new sweep with its runs (the cache answering the runs it
can), pause, resume (a cancelled sweep's cancelled runs queued again), cancel and delete.

``slopetui.sweeps`` decides what the rows hold (``sweeps.run_rows``: the lattice's points
and their cache keys) and what the actions mean to the user (``sweeps.control``).

*Delete* removes the sweep and its runs in one transaction, and only when none of its runs
is running (claimed by a worker, started or not). A worker that lost its run row would see
its writes guarded out (``claims``: every write checks ``status = 'running' AND worker_id
= me``), but ``begin`` would then point the worker's row at a run that no longer exists,
a foreign-key error inside the worker; refusing is the safe side, and cancelling first
then waiting for the running runs to finish (minutes) is always possible. The refusal is
decided inside the transaction, on the sweep's unfinished runs locked ``FOR UPDATE`` on
PostgreSQL (a claim in flight finishes first and is seen as running; later claims skip
the locked rows) and under ``BEGIN IMMEDIATE`` on SQLite (no claim in between).
Every reference to a deleted run is cleared by explicit statements, not left to the
schema's ``ON DELETE SET NULL`` alone (which needs SQLite's foreign_keys pragma on every
connection that deletes): a run of another sweep that copied its result from one of them
keeps the result and loses the pointer (``cached_from`` NULL), and so do a worker's
``run_id``, a continuation's ``from_run`` and a kept initial state's ``source_run``; the
runs' marks and the sweep's tags go with them.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from sqlalchemy import delete, insert, select, update
from sqlalchemy.orm import Session

from slopetui.store.database import Database, rows_changed
from slopetui.store.models import Continuation, InitialState, Mark, Run, Sweep, SweepTag, Worker
from slopetui.store.runs.cached_results import finished_results, result_of

#: A run's columns by name, as ``insert(Run)`` takes them.
RunRow = dict[str, object]


def insert_runs(s: Session, sweep_id: int, rows: list[RunRow]) -> int:
    """Insert the rows into the sweep, queued, or done with the result of an earlier
    computed run with the same cache key, in the caller's transaction. The rows are
    completed in place (sweep_id, status, and a cached run's result and cached_from).
    Returns how many took a cached result."""
    cached = finished_results(s, (r["cache_key"] for r in rows))  # type: ignore[misc]
    for row in rows:
        row["sweep_id"] = sweep_id
        hit = cached.get(str(row["cache_key"]))
        if hit is not None:
            row.update(result_of(hit), status="done", cached_from=hit.id)
        else:
            row["status"] = "queued"
    done = [r for r in rows if r["status"] == "done"]
    # Two bulk inserts, one per column set: executemany needs uniform rows.
    for group in (done, [r for r in rows if r["status"] == "queued"]):
        if group:
            s.execute(insert(Run), group)
    return len(done)


def insert_sweep(db: Database, *, name: str, spec: dict[str, Any], x_param: str,
                 y_param: str | None, n_runs: int, adaptive_levels: int | None,
                 rows: list[RunRow]) -> tuple[int, int]:
    """Insert a sweep and its runs (see insert_runs) in one transaction; an adaptive sweep
    (``adaptive_levels`` set) starts at its level 0. Returns (the sweep's id, how many
    runs took a cached result)."""
    with db.transaction() as s:
        sweep = Sweep(name=name, spec=spec, x_param=x_param, y_param=y_param, n_runs=n_runs,
                      adaptive_levels=adaptive_levels,
                      level=None if adaptive_levels is None else 0)
        s.add(sweep)
        s.flush()
        n_cached = insert_runs(s, sweep.id, rows)
    return sweep.id, n_cached


def set_sweep_status(db: Database, sweep_id: int, status: str,
                     allowed_from: tuple[str, ...]) -> str | None:
    """Set the sweep's status if it is one of ``allowed_from`` (else leave it); returns the
    status it has now, or None if there is no such sweep."""
    with db.transaction() as s:
        sweep = s.get(Sweep, sweep_id)
        if sweep is None:
            return None
        if sweep.status in allowed_from:
            sweep.status = status
        return sweep.status


def cancel_sweep(db: Database, sweep_id: int) -> int | None:
    """Mark the sweep cancelled and its queued runs too (running ones finish), in one
    transaction; returns how many runs it cancelled, or None if there is no such sweep."""
    with db.transaction() as s:
        sweep = s.get(Sweep, sweep_id)
        if sweep is None:
            return None
        sweep.status = "cancelled"
        return rows_changed(s.execute(update(Run).where(Run.sweep_id == sweep_id,
                                                        Run.status == "queued")
                                      .values(status="cancelled")))


def resume_sweep(db: Database, sweep_id: int,
                 allowed_from: tuple[str, ...]) -> tuple[str, int] | None:
    """Make the sweep active if its status is one of ``allowed_from`` (else leave it), and
    then put its cancelled runs back in the queue, in one transaction. Returns (the status
    it has now, how many runs were queued again), or None if there is no such sweep.

    The runs go back as they were when cancelled: cancel only changed their status (only
    queued runs are cancelled), so their attempts still count the attempts really made
    (0 for a run that never ran, more for one a dead worker's lease gave back) and the
    queue's max_attempts keeps its meaning."""
    with db.transaction() as s:
        sweep = s.get(Sweep, sweep_id)
        if sweep is None:
            return None
        if sweep.status not in allowed_from:
            return sweep.status, 0
        sweep.status = "active"
        n = rows_changed(s.execute(update(Run).where(Run.sweep_id == sweep_id,
                                                     Run.status == "cancelled")
                                   .values(status="queued")))
        return sweep.status, n


@dataclass(frozen=True)
class Deletion:
    """What ``delete_sweep`` did: nothing when ``running`` > 0.

    runs        : the sweep's runs deleted
    running     : its runs a worker holds (then nothing was deleted)
    copies_kept : runs of other sweeps that had copied their result from one of the
                  deleted runs: they keep it, with ``cached_from`` now NULL
    """

    runs: int
    running: int
    copies_kept: int


def delete_sweep(db: Database, sweep_id: int) -> Deletion | None:
    """Delete the sweep and its runs in one transaction, clearing every reference to the
    runs first (module docstring), unless one of its runs is running. None if there is no
    such sweep."""
    with db.transaction() as s:
        sweep = s.get(Sweep, sweep_id, with_for_update=True)
        if sweep is None:
            return None
        # Locked (PostgreSQL): a claim that took one of these rows before us commits first
        # and its row is read as running; claims after us skip them (SKIP LOCKED).
        unfinished = s.scalars(select(Run.status)
                               .where(Run.sweep_id == sweep_id,
                                      Run.status.in_(("queued", "running")))
                               .with_for_update()).all()
        running = sum(status == "running" for status in unfinished)
        if running:
            return Deletion(0, running, 0)
        doomed = select(Run.id).where(Run.sweep_id == sweep_id).scalar_subquery()
        bulk = {"synchronize_session": False}  # plain SQL: no ORM objects to keep in step
        copies = rows_changed(s.execute(update(Run).where(Run.cached_from.in_(doomed),
                                                          Run.sweep_id != sweep_id)
                                        .values(cached_from=None), execution_options=bulk))
        s.execute(update(Worker).where(Worker.run_id.in_(doomed)).values(run_id=None),
                  execution_options=bulk)
        s.execute(update(Continuation).where(Continuation.from_run.in_(doomed))
                  .values(from_run=None), execution_options=bulk)
        s.execute(update(InitialState).where(InitialState.source_run.in_(doomed))
                  .values(source_run=None), execution_options=bulk)
        s.execute(delete(Mark).where(Mark.run_id.in_(doomed)), execution_options=bulk)
        s.execute(delete(SweepTag).where(SweepTag.sweep_id == sweep_id), execution_options=bulk)
        runs = rows_changed(s.execute(delete(Run).where(Run.sweep_id == sweep_id),
                                      execution_options=bulk))
        s.delete(sweep)
        return Deletion(runs, 0, copies)
