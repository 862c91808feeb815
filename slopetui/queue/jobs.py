"""The life of a job (a run) in the queue: claim, begin, complete, fail, release (the
heartbeat and the requeues of every kind of job are ``slopetui.queue.registry``'s).

The statements, and why they cannot hand one run to two workers, are in
``slopetui.store.runs.claims``; this module holds what a job is and the queue's policy: how many
runs a batch may hold, when a run has used its attempts, the lease's defaults.

A worker claims a run under a lease, which lasts while its heartbeat (database time) is
younger than the lease length; ``registry.requeue_expired`` hands the runs of silent workers to
others, and fails a run after ``max_attempts``. Every write of a result is guarded by the
lease, so a worker that lost its lease cannot write a second result for a run that another
worker has taken over.

Attempts are charged when a run enters the kernel, not when it is claimed: a batch is
claimed with ``started_at`` NULL and attempts unchanged, and ``begin`` charges the runs
that are about to be computed (and stamps started_at). So when a worker dies mid-batch,
only the runs that were being computed have used an attempt; the runs it held but had not
started (``status = 'running' AND started_at IS NULL``) go back to the queue as they came.
How a worker computes a batch is slopetui.queue.run_batches (the runs' JobKind).

Each claimed run is built and checked at the claim (its parameters, its solver settings,
their grid, the state its history names): a run whose stored inputs cannot be computed
(a hand-edited store) fails at once with the reason and is dropped from the batch, which
goes on (slopetui.queue.stored_inputs).
"""

from __future__ import annotations

from collections.abc import Collection, Mapping, Sequence
from dataclasses import dataclass, replace
from functools import lru_cache
from typing import TYPE_CHECKING, Any

from core.params import PARAM_NAMES, ParameterError, Params
from slopetui.queue import stored_inputs
from slopetui.queue.cache import cache_key
from slopetui.queue.defaults import MAX_ATTEMPTS
from slopetui.store.database import Database
from slopetui.store.runs import cached_results, claims, initial_states
from slopetui.store.runs.claims import ClaimedRow

if TYPE_CHECKING:  # core.solve imports numpy: not for `slopetui --help` and `status`
    from core.history import CarriedState
    from core.solve import SolverSettings


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
    #: The final state its history names, read at the claim (None: a named history).
    carried: CarriedState | None = None


#: The claimed columns a run's inputs are built from (NULL in none of them).
_INPUTS = (*PARAM_NAMES, "method", "dt", "t_end", "window", "lyap", "history", "stop")


def _job(m: ClaimedRow, started: bool, states: Mapping[str, bytes]) -> Job:
    """The job of a claimed row, its inputs checked as the engine will check them (the
    grid included) and the state its history names taken from ``states`` (by name).
    Raises one of stored_inputs.INPUT_ERRORS (ParameterError naming the field) for inputs
    that cannot be computed."""
    from core.history import STATE_PREFIX, CarriedState
    from core.history import start as history_start
    from core.solve import SolverSettings, make_grid
    stored_inputs.present(m, _INPUTS)
    params = Params(**{n: getattr(m, n) for n in PARAM_NAMES})
    if not isinstance(m.lyap, bool):
        raise ParameterError("lyap", m.lyap, "true or false")
    settings = SolverSettings(method=m.method, dt=m.dt, t_end=m.t_end, window=m.window,
                              lyap=m.lyap, history=m.history, stop=m.stop)
    grid = make_grid(params, settings)  # dt <= tau, the steps' and the memory's limits
    carried = None
    if settings.history.startswith(STATE_PREFIX):
        blob = states.get(settings.history)
        if blob is None:
            raise ParameterError("history", settings.history, "a final state kept in this "
                                 "store (initial_states holds none of that name)")
        carried = CarriedState.from_bytes(blob)
        # the state's name, tau, step and length against the run's, as the kernel will
        history_start(params, grid.dt, grid.n_delay, settings.history, carried)
    return Job(m.id, m.sweep_id, m.attempts, m.cache_key, params, settings, started, carried)


def _built(db: Database, worker_id: str, rows: Sequence[ClaimedRow], started: bool
           ) -> list[Job]:
    """The jobs of the claimed rows, by id; a row whose inputs cannot be computed is
    failed at once with the reason (claims.refuse), logged in one line, and left out."""
    from core.history import STATE_PREFIX
    names = {m.history for m in rows
             if isinstance(m.history, str) and m.history.startswith(STATE_PREFIX)}
    states = {name: blob for name in names
              if (blob := initial_states.load_state(db, name)) is not None}
    built: list[Job] = []
    refused: dict[int, str] = {}
    for m in rows:
        try:
            built.append(_job(m, started, states))
        except stored_inputs.INPUT_ERRORS as exc:
            refused[m.id] = stored_inputs.reason(exc)
    if refused:
        claims.refuse(db, worker_id, refused)
        for run_id, text in sorted(refused.items()):
            stored_inputs.log_refused("run", run_id, text)
    return sorted(built, key=lambda job: job.run_id)


def claim_batch(db: Database, worker_id: str, limit: int,
                batched: Collection[str] | None = None) -> list[Job]:
    """Claim up to ``limit`` queued runs that share the oldest queued run's solver settings
    and tau (oldest first; the batched kernels' lanes share tau), in one transaction; []
    if nothing is queued. They are all leased to the
    worker, but no attempt is charged until ``begin``: if the worker dies, requeue_worker /
    requeue_expired hand back the runs it never started as they were.

    batched : the methods the worker computes a batch of together; a run of another method
              is claimed alone. A worker computing a batch run by run holds runs that
              idle workers could have started (one worker held 30 of 32 RK4 runs while
              the other waited, when RK4 had no batched kernel).

    A claimed run whose inputs cannot be computed fails at once (``_built``); if that
    leaves nothing, the next batch is claimed: each round fails at least one run for good,
    so this ends.
    """
    while rows := claims.claim_batch(db, worker_id, limit, batched):
        if batch := _built(db, worker_id, rows, started=False):
            return batch
    return []


def begin(db: Database, batch: list[Job], worker_id: str) -> list[Job]:
    """The runs of ``batch`` go into the kernel now: charge each an attempt and point the
    worker at the first. Returns the jobs still held (a lost lease drops a job), with
    their attempts counted."""
    todo = [job for job in batch if not job.started]
    attempts = claims.begin(db, worker_id, [job.run_id for job in todo],
                            batch[0].run_id if batch else None)
    return [job if job.started else replace(job, attempts=attempts[job.run_id], started=True)
            for job in batch if job.started or job.run_id in attempts]


def complete(db: Database, job: Job, worker_id: str, record: dict[str, Any],
             cached_from: int | None = None) -> bool:
    """Write the result; False if the lease was lost meanwhile (nothing is written). A
    computed result names this process's engine (engine_digest), which need not be the
    one that queued the run (a worker started from other code), and its cache key
    follows; a result from the cache keeps the run's (the hit's key is the run's)."""
    engine = None
    if cached_from is None:
        digest = engine_digest()
        inputs = {**{n: getattr(job.params, n) for n in PARAM_NAMES}, "method": job.settings.method,
                  "dt": job.settings.dt, "t_end": job.settings.t_end, "window": job.settings.window,
                  "lyap": job.settings.lyap, "history": job.settings.history,
                  "stop": job.settings.stop, "engine": digest}
        engine = (digest, cache_key(inputs))
    return claims.complete(db, job.run_id, worker_id, record, cached_from, engine)


@lru_cache(maxsize=1)
def engine_digest() -> str:
    """The digest of the engine this process computes with (core.jit_cache.source_digest),
    read once, at the worker's start (worker_process): the sources on disk may change
    under a running worker (a git pull, an upgrade), and the modules it loaded by then
    (the kernels of its warm-up) do not. Not every module: core modules imported at their
    first use (core.certify, core.shooting, core.continuation, ...) are read from disk
    then, so a worker running while core/ changes can compute with a mix of both versions
    under the old digest. Restart the workers after changing core/."""
    from core.jit_cache import source_digest
    return source_digest()


def cached_result(db: Database, job: Job) -> tuple[int, dict[str, Any]] | None:
    """A finished run with the job's cache key (one finished after the job was queued)."""
    return cached_results.cached_result(db, job.cache_key)


def fail(db: Database, job: Job, worker_id: str, error: str,
         max_attempts: int = MAX_ATTEMPTS) -> str | None:
    """Record an error: back to the queue, or failed after max_attempts. Returns the new
    status, or None if the lease was lost meanwhile."""
    give_up = job.attempts >= max_attempts
    written = claims.lease.fail(db, job.run_id, worker_id, error, give_up=give_up)
    return ("failed" if give_up else "queued") if written else None


def release(db: Database, job: Job, worker_id: str) -> bool:
    """Give a run back unfinished (a shutdown, not its fault): a started run's attempt is
    given back too."""
    return claims.lease.release(db, job.run_id, worker_id, started=job.started)
