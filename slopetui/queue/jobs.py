"""The life of a job (a run) in the queue: claim, begin, heartbeat, complete, fail, release.

A worker claims a run with one ``UPDATE ... WHERE id = (SELECT ... LIMIT 1) RETURNING``:
inside SQLite's BEGIN IMMEDIATE, or with ``FOR UPDATE SKIP LOCKED`` on PostgreSQL, two
workers can never claim the same run. Its lease lasts while its heartbeat (database time)
is younger than the lease length; ``requeue_expired`` hands the runs of silent workers to
others, and fails a run after ``max_attempts``. Every write of a result is guarded by
``status = 'running' AND worker_id = me``, so a worker that lost its lease cannot write a
second result for a run that another worker has taken over.

Attempts are charged when a run enters the kernel, not when it is claimed: a batch is
claimed with ``started_at`` NULL and attempts unchanged, and ``begin`` charges the runs
that are about to be computed (and stamps started_at). So when a worker dies mid-batch,
only the runs that were being computed have used an attempt; the runs it held but had not
started (``status = 'running' AND started_at IS NULL``) go back to the queue as they came.
``claim`` (one run, computed at once) claims and begins in one statement.
"""

from __future__ import annotations

from collections.abc import Collection
from dataclasses import dataclass, replace
from datetime import timedelta
from typing import TYPE_CHECKING, Any

from sqlalchemy import bindparam, func, select, update
from sqlalchemy.orm import Session

from core.params import PARAM_NAMES, Params
from slopetui.queue.cache import RESULT_FIELDS
from slopetui.queue.defaults import LEASE_S, MAX_ATTEMPTS
from slopetui.store.database import Database, rows_changed
from slopetui.store.db_time import db_now
from slopetui.store.models import Run, Sweep, Worker

if TYPE_CHECKING:  # core.solve imports numpy: not for `slopetui --help` and `status`
    from core import SolverSettings



@dataclass(frozen=True)
class Job:
    """A claimed run: what to compute. ``attempts`` counts this attempt once ``started``."""

    run_id: int
    sweep_id: int
    attempts: int
    cache_key: str
    params: Params
    settings: SolverSettings
    #: Charged an attempt (``begin``): a release gives that attempt back.
    started: bool = False


_CLAIM_COLUMNS = (Run.id, Run.sweep_id, Run.attempts, Run.cache_key, *(
    getattr(Run, n) for n in (*PARAM_NAMES, "method", "dt", "t_end", "window", "lyap")))


def _job(row: Any, started: bool) -> Job:
    from core import SolverSettings
    m = row._mapping
    params = Params(**{n: m[n] for n in PARAM_NAMES})
    settings = SolverSettings(method=m["method"], dt=m["dt"], t_end=m["t_end"],
                              window=m["window"], lyap=m["lyap"])
    return Job(m["id"], m["sweep_id"], m["attempts"], m["cache_key"], params, settings,
               started)


# The hot path (claim, complete) runs prebuilt statements with bound parameters: building
# a 13-column UPDATE anew per job cost ~2 ms of SQLAlchemy coercion, 10x SQLite's own work.
_OLDEST_QUEUED = (select(Run.id).join(Sweep, Sweep.id == Run.sweep_id)
                  .where(Run.status == "queued", Sweep.status == "active")
                  .order_by(Run.id).limit(1)
                  .with_for_update(skip_locked=True, of=Run)  # PostgreSQL; SQLite ignores it
                  .scalar_subquery())
_CLAIM = (update(Run).where(Run.id == _OLDEST_QUEUED, Run.status == "queued")
          .values(status="running", worker_id=bindparam("wid"), attempts=Run.attempts + 1,
                  started_at=db_now(), heartbeat_at=db_now(), error=None)
          .returning(*_CLAIM_COLUMNS))
_WORKER_ON = (update(Worker).where(Worker.id == bindparam("wid"))
              .values(run_id=bindparam("rid"), heartbeat_at=db_now()))
#: The lease holder's guard on every write to a claimed run (rid, wid).
_HOLDING = ((Run.id == bindparam("rid")) & (Run.status == "running")
            & (Run.worker_id == bindparam("wid")))
_COMPLETE = (update(Run).where(_HOLDING)
             .values(status="done", finished_at=db_now(), error=None,
                     # a run served from the cache was never started
                     started_at=func.coalesce(Run.started_at, db_now()),
                     cached_from=bindparam("from_id"),
                     **{name: bindparam(f"r_{name}") for name in RESULT_FIELDS}))
_WORKER_DONE = (update(Worker).where(Worker.id == bindparam("wid"))
                .values(run_id=None, heartbeat_at=db_now(),
                        jobs_done=Worker.jobs_done + bindparam("n_done")))


# A batch: the oldest queued run's solver settings, then up to n queued runs with the same
# settings (they can share one call of the batched kernels, core.batch), oldest first.
_OLDEST_SETTINGS = (select(Run.method, Run.dt, Run.t_end, Run.window, Run.lyap)
                    .join(Sweep, Sweep.id == Run.sweep_id)
                    .where(Run.status == "queued", Sweep.status == "active")
                    .order_by(Run.id).limit(1))
_COMPATIBLE = (select(Run.id).join(Sweep, Sweep.id == Run.sweep_id)
               .where(Run.status == "queued", Sweep.status == "active",
                      Run.method == bindparam("b_method"), Run.dt == bindparam("b_dt"),
                      Run.t_end == bindparam("b_t_end"), Run.window == bindparam("b_window"),
                      Run.lyap == bindparam("b_lyap"))
               .order_by(Run.id).limit(bindparam("n"))
               .with_for_update(skip_locked=True, of=Run))
# Claimed, not started: no attempt charged, started_at NULL until begin (module docstring).
_CLAIM_BATCH = (update(Run).where(Run.id.in_(_COMPATIBLE), Run.status == "queued")
                .values(status="running", worker_id=bindparam("wid"), started_at=None,
                        heartbeat_at=db_now())
                .returning(*_CLAIM_COLUMNS))
_BEGIN = (update(Run).where(Run.id.in_(bindparam("rids", expanding=True)),
                            Run.status == "running", Run.worker_id == bindparam("wid"),
                            Run.started_at.is_(None))
          .values(attempts=Run.attempts + 1, started_at=db_now(), heartbeat_at=db_now(),
                  error=None)
          .returning(Run.id, Run.attempts))


def claim_batch(db: Database, worker_id: str, limit: int,
                batched: Collection[str] | None = None) -> list[Job]:
    """Claim up to ``limit`` queued runs that share the oldest queued run's solver settings
    (oldest first), in one transaction; [] if nothing is queued. They are all leased to the
    worker, but no attempt is charged until ``begin``: if the worker dies, requeue_worker /
    requeue_expired hand back the runs it never started as they were.

    batched : the methods the worker computes a batch of together; a run of another method
              is claimed alone. A worker computing 32 RK4 runs one after the other held
              runs that idle workers could have started (one worker held 30 while the
              other waited).
    """
    with db.connection() as conn:
        settings = conn.execute(_OLDEST_SETTINGS).first()
        if settings is None:
            return []
        if batched is not None and settings.method not in batched:
            limit = 1
        rows = conn.execute(_CLAIM_BATCH, {"wid": worker_id, "n": limit, **{
            f"b_{name}": value for name, value in settings._mapping.items()}}).all()
    return sorted((_job(row, started=False) for row in rows), key=lambda job: job.run_id)


def begin(db: Database, batch: list[Job], worker_id: str) -> list[Job]:
    """The runs of ``batch`` go into the kernel now: charge each an attempt and point the
    worker at the first. Returns the jobs still held (a lost lease drops a job), with
    their attempts counted."""
    todo = [job for job in batch if not job.started]
    with db.connection() as conn:
        attempts = dict(conn.execute(_BEGIN, {"rids": [job.run_id for job in todo],
                                              "wid": worker_id}).all()) if todo else {}
        if batch:
            conn.execute(_WORKER_ON, {"wid": worker_id, "rid": batch[0].run_id})
    return [job if job.started else replace(job, attempts=attempts[job.run_id], started=True)
            for job in batch if job.started or job.run_id in attempts]


def claim(db: Database, worker_id: str) -> Job | None:
    """Claim the oldest queued run of an active sweep, or None if there is none."""
    with db.connection() as conn:
        row = conn.execute(_CLAIM, {"wid": worker_id}).first()
        if row is not None:
            conn.execute(_WORKER_ON, {"wid": worker_id, "rid": row.id})
    return None if row is None else _job(row, started=True)


def complete(db: Database, job: Job, worker_id: str, record: dict[str, Any],
             cached_from: int | None = None) -> bool:
    """Write the result; False if the lease was lost meanwhile (nothing is written)."""
    values = {f"r_{name}": record[name] for name in RESULT_FIELDS}
    with db.connection() as conn:
        done = conn.execute(_COMPLETE, {"rid": job.run_id, "wid": worker_id,
                                        "from_id": cached_from, **values}).rowcount == 1
        conn.execute(_WORKER_DONE, {"wid": worker_id, "n_done": int(done)})
    return done


_CACHED = (select(Run.id, *(getattr(Run, name) for name in RESULT_FIELDS))
           .where(Run.cache_key == bindparam("key"), Run.status == "done",
                  Run.inferred.is_(False))  # an inferred label is not a result
           .order_by(Run.id).limit(1))


def cached_result(db: Database, job: Job) -> tuple[int, dict[str, Any]] | None:
    """A finished run with the job's cache key (one finished after the job was queued)."""
    with db.reader.connect() as conn:
        row = conn.execute(_CACHED, {"key": job.cache_key}).first()
    if row is None:
        return None
    m = row._mapping
    return m["id"], {name: m[name] for name in RESULT_FIELDS}


def fail(db: Database, job: Job, worker_id: str, error: str,
         max_attempts: int = MAX_ATTEMPTS) -> str | None:
    """Record an error: back to the queue, or failed after max_attempts. Returns the new
    status, or None if the lease was lost meanwhile."""
    status = "failed" if job.attempts >= max_attempts else "queued"
    with db.transaction() as s:
        n = rows_changed(s.execute(update(Run).where(_HOLDING)
                      .values(status=status, error=error[-4000:],
                              worker_id=worker_id if status == "failed" else None,
                              finished_at=db_now() if status == "failed" else None),
                      {"rid": job.run_id, "wid": worker_id}))
        s.execute(update(Worker).where(Worker.id == worker_id).values(run_id=None))
    return status if n == 1 else None


def release(db: Database, job: Job, worker_id: str) -> bool:
    """Give a run back unfinished (a shutdown, not its fault): a started run's attempt is
    given back too."""
    with db.transaction() as s:
        n = rows_changed(s.execute(update(Run).where(_HOLDING)
                      .values(status="queued", worker_id=None,
                              attempts=Run.attempts - int(job.started)),
                      {"rid": job.run_id, "wid": worker_id}))
        s.execute(update(Worker).where(Worker.id == worker_id).values(run_id=None))
    return n == 1


def heartbeat(db: Database, worker_id: str) -> None:
    """Extend the leases of every run the worker holds (one, or a batch) and mark the
    worker alive."""
    with db.transaction() as s:
        s.execute(update(Worker).where(Worker.id == worker_id)
                  .values(heartbeat_at=db_now()))
        s.execute(update(Run).where(Run.status == "running", Run.worker_id == worker_id)
                  .values(heartbeat_at=db_now()))


def _requeue(s: Session, where: Any, reason: str, max_attempts: int) -> tuple[int, int]:
    # Runs held but never started cost nothing and carry no new error: back as they were.
    unstarted = s.execute(update(Run).where(where, Run.started_at.is_(None))
                          .values(status="queued", worker_id=None))
    failed = s.execute(update(Run).where(where, Run.attempts >= max_attempts)
                       .values(status="failed", finished_at=db_now(),
                               error=f"{reason}; gave up after {max_attempts} attempts"))
    requeued = s.execute(update(Run).where(where)
                         .values(status="queued", worker_id=None, error=reason))
    return rows_changed(requeued) + rows_changed(unstarted), rows_changed(failed)


def requeue_expired(db: Database, lease_s: float = LEASE_S,
                    max_attempts: int = MAX_ATTEMPTS) -> tuple[int, int]:
    """Runs whose lease expired go back to the queue (or fail after max_attempts).
    Returns (requeued, failed)."""
    with db.transaction() as s:
        cutoff = db.now(s) - timedelta(seconds=lease_s)
        expired = (Run.status == "running") & (Run.heartbeat_at < cutoff)
        return _requeue(s, expired, f"lease expired: no heartbeat for {lease_s:g} s",
                        max_attempts)


def requeue_worker(db: Database, worker_id: str, reason: str,
                   max_attempts: int = MAX_ATTEMPTS) -> tuple[int, int]:
    """The runs of a worker known to be dead go back at once, without waiting for the
    lease. Returns (requeued, failed)."""
    with db.transaction() as s:
        held = (Run.status == "running") & (Run.worker_id == worker_id)
        out = _requeue(s, held, reason, max_attempts)
        s.execute(update(Worker).where(Worker.id == worker_id)
                  .values(run_id=None, stopped_at=db_now()))
        return out
