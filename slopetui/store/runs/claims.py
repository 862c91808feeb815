"""The statements of a claimed run's life: claim (a batch), begin, complete, refuse, and
the runs' lease (``lease``: fail, release, heartbeat, requeue, shared with every job kind,
slopetui.store.jobs.leases). ``slopetui.queue.jobs`` holds the policy (what a job is, when a
run has used up its attempts) and calls these; each one here is one transaction.

Inside SQLite's BEGIN IMMEDIATE, or with ``FOR UPDATE SKIP LOCKED`` on PostgreSQL, two
workers can never claim the same run. Every write of a result is guarded by the lease
(``status = 'running' AND worker_id = me``), so a worker that lost its lease cannot write
a second result for a run that another worker has taken over; the worker's row is
written after the runs' (the lock order, slopetui.store.jobs.leases).

A batch (``claim_batch``) is the oldest queued run of an active sweep that no other worker
is claiming, and the queued runs that share its solver settings (the stop rule among
them: a batch's lanes stop by one rule), history and tau, oldest first: the batched
kernels' lanes share tau (one delay ring length, one step grid, core.batch), and a plane
of n x m points still fills batches, with n runs per tau. Its
runs are selected and locked first, in a CTE (``FOR UPDATE SKIP LOCKED`` on PostgreSQL),
and the ``UPDATE`` takes what it picked, in the same transaction.

A batch is claimed with ``started_at`` NULL and attempts unchanged; ``begin`` charges the
runs that are about to be computed (and stamps started_at), so the runs a dead worker held
but had not started (``status = 'running' AND started_at IS NULL``) go back to the queue as
they came.
"""

from __future__ import annotations

from collections.abc import Collection, Mapping
from dataclasses import dataclass
from typing import Any

from sqlalchemy import bindparam, func, select, update

from core.result_fields import RESULT_NAMES
from slopetui.store.database import Database
from slopetui.store.db_time import db_now
from slopetui.store.jobs.leases import Lease
from slopetui.store.jobs.point_jobs import columns, record_of
from slopetui.store.models import Run, Sweep, Worker


@dataclass(frozen=True, slots=True)
class ClaimedRow:
    """What a claim returns of each run: its ids, attempts, cache key, parameters and
    solver settings (what a worker needs to compute it), as stored: a hand-edited store
    may hold NULL or a value of another type in any of them (slopetui.queue.stored_inputs
    checks them)."""

    id: int
    sweep_id: int
    attempts: int
    cache_key: str
    a: float
    b: float
    c: float
    d: float
    k: float
    v: float
    tau: float
    delta: float
    method: str
    dt: float
    t_end: float
    window: float
    lyap: bool
    history: str
    stop: str


_CLAIM_COLUMNS = tuple(columns(Run, ClaimedRow))
#: The runs' lease: the worker's row names the run it computes (workers.run_id).
lease = Lease(Run, pointed=True)

# The hot path (claim, complete) runs prebuilt statements with bound parameters: building
# a 13-column UPDATE anew per job cost ~2 ms of SQLAlchemy coercion, 10x SQLite's own work.
_WORKER_ON = (update(Worker).where(Worker.id == bindparam("wid"))
              .values(run_id=bindparam("rid"), heartbeat_at=db_now()))
_COMPLETE = (update(Run).where(lease.holding)
             .values(status="done", finished_at=db_now(), error=None,
                     # a run served from the cache was never started
                     started_at=func.coalesce(Run.started_at, db_now()),
                     cached_from=bindparam("from_id"),
                     **{name: bindparam(f"r_{name}") for name in RESULT_NAMES}))
# A computed run names the engine that computed it, and its key follows (queue.jobs.complete)
_COMPLETE_BY = _COMPLETE.values(engine=bindparam("engine"), cache_key=bindparam("key"))
_WORKER_DONE = (update(Worker).where(Worker.id == bindparam("wid"))
                .values(run_id=None, heartbeat_at=db_now(),
                        jobs_done=Worker.jobs_done + bindparam("n_done")))


# A batch: the solver settings and tau of the oldest queued run no other worker is
# claiming, then up to n queued runs with the same settings and tau (they share one call of
# the batched kernels, core.batch, whose lanes share tau), oldest first. The oldest run is
# locked as it is read (PostgreSQL; SQLite's BEGIN IMMEDIATE serialises claims): a worker
# claiming at the same time reads the next one instead of settings whose runs it would
# then find all taken, and come back with nothing while runs of other tau wait.
_BATCH_KEY = (Run.method, Run.dt, Run.t_end, Run.window, Run.lyap, Run.history, Run.stop,
              Run.tau)
_OLDEST_SETTINGS = (select(*_BATCH_KEY, Run.id)
                    .join(Sweep, Sweep.id == Run.sweep_id)
                    .where(Run.status == "queued", Sweep.status == "active")
                    .order_by(Run.id).limit(1)
                    .with_for_update(skip_locked=True, of=Run))
_COMPATIBLE = (select(Run.id).join(Sweep, Sweep.id == Run.sweep_id)
               .where(Run.status == "queued", Sweep.status == "active",
                      *(column == bindparam(f"b_{column.key}") for column in _BATCH_KEY))
               .order_by(Run.id).limit(bindparam("n"))
               .with_for_update(skip_locked=True, of=Run))
# Claimed, not started: no attempt charged, started_at NULL until begin (module docstring).
# The runs are selected and locked first, in a CTE, and the UPDATE takes what it picked:
# with ``WHERE id IN (SELECT ... LIMIT n FOR UPDATE SKIP LOCKED)`` PostgreSQL may evaluate
# the sub-select again for each row it updates, and asking for 1 run returned all 50
# queued (tests/integration/test_claims_postgres.py; 17 to 43 with two pools).
_PICKED = _COMPATIBLE.cte("picked")
_CLAIM_BATCH = (update(Run).where(Run.id == _PICKED.c.id, Run.status == "queued")
                .values(status="running", worker_id=bindparam("wid"), started_at=None,
                        heartbeat_at=db_now())
                .returning(*_CLAIM_COLUMNS))
# The oldest run alone, by id: one whose settings hold a NULL (a hand-edited store), which
# equals nothing in SQL, so that _COMPATIBLE would never take it (claim_batch).
_CLAIM_ALONE = (update(Run).where(Run.id == bindparam("rid"), Run.status == "queued")
                .values(status="running", worker_id=bindparam("wid"), started_at=None,
                        heartbeat_at=db_now())
                .returning(*_CLAIM_COLUMNS))
#: A held run whose stored inputs cannot be computed fails at once, without an attempt.
_REFUSE = (update(Run).where(lease.holding)
           .values(status="failed", error=bindparam("reason"), finished_at=db_now(),
                   started_at=func.coalesce(Run.started_at, db_now())))
_BEGIN = (update(Run).where(Run.id.in_(bindparam("rids", expanding=True)),
                            Run.status == "running", Run.worker_id == bindparam("wid"),
                            Run.started_at.is_(None))
          .values(attempts=Run.attempts + 1, started_at=db_now(), heartbeat_at=db_now(),
                  error=None)
          .returning(Run.id, Run.attempts))


def claim_batch(db: Database, worker_id: str, limit: int,
                batched: Collection[str] | None) -> list[ClaimedRow]:
    """Lease to the worker the oldest ``limit`` queued runs of active sweeps that share
    the oldest queued run's solver settings, history and tau (the oldest no other worker
    is claiming), in one transaction, without charging an attempt; [] if nothing is
    queued. A run whose method is not in ``batched`` (None: every method), or whose
    history is not the constant one (the batched kernels know no other, core.batch), is
    claimed alone, and so is a run whose settings hold a NULL (a hand-edited store: NULL
    equals nothing, so no batch would ever take it, and every later claim would stop at
    it; the worker fails it, slopetui.queue.jobs). Returned not in id order: the caller
    sorts."""
    with db.connection() as conn:
        oldest = conn.execute(_OLDEST_SETTINGS).first()
        if oldest is None:
            return []
        key = {name: value for name, value in oldest._mapping.items() if name != "id"}
        if any(value is None for value in key.values()):
            rows = conn.execute(_CLAIM_ALONE, {"wid": worker_id, "rid": oldest.id}).all()
            return [record_of(ClaimedRow, row) for row in rows]
        if batched is not None and (oldest.method not in batched
                                    or oldest.history != "constant"):
            limit = 1
        rows = conn.execute(_CLAIM_BATCH, {"wid": worker_id, "n": limit, **{
            f"b_{name}": value for name, value in key.items()}}).all()
    return [record_of(ClaimedRow, row) for row in rows]


def refuse(db: Database, worker_id: str, reasons: Mapping[int, str]) -> int:
    """Fail at once, with its reason, each held run of ``reasons`` (by id) whose stored
    inputs cannot be computed: the same values would fail in every worker, so no attempt
    is charged and none retried. Returns how many it failed (a run whose lease was lost
    meanwhile is left to its new holder)."""
    with db.connection() as conn:
        return sum(conn.execute(_REFUSE, {"jid": rid, "wid": worker_id,
                                          "reason": reason[-4000:]}).rowcount
                   for rid, reason in reasons.items())


def begin(db: Database, worker_id: str, run_ids: list[int], current: int | None) -> dict[int, int]:
    """Charge an attempt to each of the runs (claimed, not started) the worker still holds,
    stamp their started_at, and point the worker at run ``current`` (None: leave it), in
    one transaction. Returns the attempts of the runs it charged, by id: a run missing
    from it was lost with its lease."""
    with db.connection() as conn:
        attempts: dict[int, int] = dict(conn.execute(  # (id, attempts) rows
            _BEGIN, {"rids": run_ids, "wid": worker_id}).all()) if run_ids else {}
        if current is not None:
            conn.execute(_WORKER_ON, {"wid": worker_id, "rid": current})
    return attempts


def complete(db: Database, run_id: int, worker_id: str, record: Mapping[str, Any],
             cached_from: int | None = None, engine: tuple[str, str] | None = None) -> bool:
    """Write the result fields of ``record`` (core.result_fields) if the worker still holds
    the run, and count the job on the worker; False if the lease was lost meanwhile
    (nothing is written). ``engine``: (the digest of the engine that computed it, the
    run's cache key with that digest), written with the result."""
    values = {f"r_{name}": record[name] for name in RESULT_NAMES}
    statement, named = _COMPLETE, {}
    if engine is not None:
        statement, named = _COMPLETE_BY, {"engine": engine[0], "key": engine[1]}
    with db.connection() as conn:
        done = conn.execute(statement, {"jid": run_id, "wid": worker_id,
                                        "from_id": cached_from, **values, **named}).rowcount == 1
        conn.execute(_WORKER_DONE, {"wid": worker_id, "n_done": int(done)})
    return done
