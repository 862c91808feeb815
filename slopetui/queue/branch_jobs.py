"""A continuation as a job of the queue: submitted, claimed by a worker under a lease,
computed point by point with each point saved as soon as it is known, resumed from the
saved points by whoever takes it over, finished with its bifurcations.

The policy beside the runs' (slopetui.queue.jobs; what a step in the compute thread
comes to, shared with hysteresis sweeps, is slopetui.queue.thread_steps):

* A worker claims a continuation before runs (``CONTINUATIONS`` comes first in
  slopetui.queue.registry): a branch is asked for interactively and takes one worker for
  seconds to minutes, while a sweep's runs keep the others busy.
* Each point is saved by the lease holder only, as the next one (slopetui.store.jobs
  .continuations.save_point): a killed worker loses at most the point it was computing.
* A stop (SIGTERM, the pool stopping) comes between two points: the continuation goes
  back to the queue with its attempt given back; an abort gives it back at once and
  leaves the point in progress unsaved.
* No orbit to start from (OrbitError at the start) is an answer, not a crash: the job
  fails at once with the reason, no retry. Any other error is retried up to
  max_attempts, as for runs.
* A row whose stored inputs cannot be computed (a hand-edited store) fails at its claim
  with the reason, and the next one is claimed (slopetui.queue.stored_inputs).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from core.jit_cache import source_digest
from core.params import PARAM_NAMES, ParameterError, Params, check_finite, check_positive
from slopetui.queue import stored_inputs
from slopetui.queue.jobs import engine_digest
from slopetui.queue.kinds import Activity, Computing, JobKind
from slopetui.queue.thread_steps import HeldJob, Runner, Stops
from slopetui.store.database import Database
from slopetui.store.jobs import continuations
from slopetui.store.jobs.continuations import ContinuationRow, SavedBranchPoint

if TYPE_CHECKING:  # numpy, scipy and numba: loaded by the worker that computes a branch
    from core.branch_start import BranchSpec, SavedPoint
    from core.continuation import Branch

log = logging.getLogger("slopetui.worker")

@dataclass(frozen=True)
class BranchJob:
    """A claimed continuation: what to compute; ``attempts`` counts this one."""

    id: int
    attempts: int
    spec: BranchSpec


def fields_of(spec: BranchSpec, from_run: int | None = None) -> dict[str, Any]:
    """The continuations row of a spec (queued, with the engine's digest)."""
    return {"param": spec.name, "start": "hopf" if spec.from_hopf else "orbit",
            "hopf_branch": spec.hopf_branch if spec.from_hopf else None,
            **{n: getattr(spec.params, n) for n in PARAM_NAMES}, "from_run": from_run,
            "dt": spec.dt, "end_value": spec.end, "max_points": spec.max_points,
            "max_step": spec.max_step, "engine": source_digest(), "status": "queued"}


def submit(db: Database, spec: BranchSpec, from_run: int | None = None) -> int:
    """Queue a continuation; returns its id."""
    return continuations.submit(db, fields_of(spec, from_run))


def spec_of(row: ContinuationRow) -> BranchSpec:
    """The spec a continuations row asks for, checked: one of stored_inputs.INPUT_ERRORS
    (ParameterError naming the column) for values it cannot be computed from."""
    from core.branch_start import BranchSpec
    stored_inputs.present(row, (*PARAM_NAMES, "param", "start", "dt", "max_points",
                                "max_step"))
    params = Params(**{n: getattr(row, n) for n in PARAM_NAMES})
    if row.param not in PARAM_NAMES:
        raise ParameterError("param", row.param, f"one of {', '.join(PARAM_NAMES)}")
    if row.start not in ("hopf", "orbit"):
        raise ParameterError("start", row.start, "hopf or orbit")
    end = None if row.end_value is None else check_finite("end_value", row.end_value)
    from_hopf = row.start == "hopf"
    if from_hopf:  # the n-th Hopf point: never a NULL taken for the first
        stored_inputs.present(row, ("hopf_branch",))
    return BranchSpec(params, row.param, stored_inputs.orbit_step(params, row.dt),
                      from_hopf, end,
                      stored_inputs.whole("max_points", row.max_points, 1),
                      check_positive("max_step", row.max_step),
                      stored_inputs.whole("hopf_branch", row.hopf_branch, 1) if from_hopf else 1)


def claim(db: Database, worker_id: str) -> BranchJob | None:
    """Claim the oldest queued continuation (one attempt charged), or None; one whose
    stored inputs cannot be computed fails at once with the reason, and the next one is
    claimed."""
    return stored_inputs.claim_computable(
        continuations, continuations.claim, "continuation", db, worker_id,
        lambda row: BranchJob(row.id, row.attempts, spec_of(row)))


def point_fields(branch: Branch) -> dict[str, Any]:
    """The branch_points row of the branch's last point: what the faces read and what a
    resumption needs (core.branch_start.SavedPoint)."""
    import numpy as np

    from core.branch_start import SavedPoint
    saved = SavedPoint.of(branch)
    point = branch.points[-1]
    mult = point.multipliers
    lead = mult.leading
    return {"idx": len(branch.points) - 1, "value": point.value, "period": point.period,
            "amplitude": point.amplitude, "stable": point.stable,
            "unstable_count": mult.unstable_count, "leading_re": lead.real,
            "leading_im": lead.imag,
            "multipliers": [[float(m.real), float(m.imag)] for m in mult.values],
            "flow_index": mult.flow_index, "translation": float(mult.translation),
            "step": saved.step,
            "state": np.concatenate((saved.y, saved.t)).astype("<f8").tobytes()}


def saved_of(row: SavedBranchPoint) -> SavedPoint:
    """A saved point back from its branch_points row."""
    import numpy as np

    from core.branch_start import SavedPoint
    from core.floquet import Multipliers
    state = np.frombuffer(row.state, dtype="<f8")
    half = state.size // 2
    values = np.array([complex(re, im) for re, im in row.multipliers])
    return SavedPoint(state[:half].copy(), state[half:].copy(), row.amplitude,
                      Multipliers(values, row.flow_index, row.translation), row.step)


def bifurcation_fields(bif: Any) -> dict[str, Any]:
    return {"type": bif.type, "value": bif.value, "period": bif.period,
            "mu_re": bif.multiplier.real, "mu_im": bif.multiplier.imag,
            "reason": bif.reason or None}


def _no_branch(error: BaseException) -> str | None:
    """No orbit to start from is an answer, not a crash: recorded at once, no retry."""
    from core.orbit import OrbitError
    return f"no branch: {error}" if isinstance(error, OrbitError) else None


def compute(db: Database, wid: str, job: BranchJob, run: Runner, control: Stops,
            max_attempts: int) -> None:
    """Compute the claimed continuation to its end, saving each point (see the module
    docstring for stops, aborts and errors)."""
    from core.branch_start import MIN_STEP, past_end, resume, start
    from core.continuation import bifurcations, check_end, step
    from core.lyapunov_coefficient import first_lyapunov
    spec = job.spec
    rows = continuations.saved_points(db, job.id)
    try:  # in this thread: a point that cannot be read back would kill the worker
        saved = [saved_of(r) for r in rows]
    except stored_inputs.INPUT_ERRORS as exc:
        stored_inputs.refuse(continuations, "continuation", db, wid, job.id, ValueError(
            f"a saved point (branch_points) cannot be read back: {exc}"))
        return

    def begin() -> tuple[Branch, tuple[float, float] | None]:
        if saved:
            return resume(spec, saved), None
        branch, hopf = start(spec)
        return branch, None if hopf is None else (hopf.value, hopf.period)

    held = HeldJob(db, wid, job.id, job.attempts, "continuation", continuations, run, control,
                   max_attempts, _no_branch)
    if (begun := held.step(begin)) is None:
        return
    (branch, hopf), spent = begun
    log.info("continuation %d in %s from %s: %s (%d saved points)", job.id, spec.name,
             f"Hopf point {spec.hopf_branch}" if spec.from_hopf else "an orbit",
             "resumed" if saved else "started", len(saved))

    def stop(point: Any) -> bool:
        return past_end(spec, branch.points[0].value, point)

    check_end(branch, stop)
    while True:
        if held.stopped():
            return
        if (stepped := held.step(lambda: step(branch, stop, spec.max_points, MIN_STEP))) is None:
            return
        point, took = stepped
        spent += took
        if point is None:
            break
        if not continuations.save_point(db, job.id, wid, point_fields(branch), spent,
                                        hopf if len(branch.points) == 1 else None,
                                        engine=engine_digest()):
            log.warning("continuation %d: lease lost; the point is not saved", job.id)
            return
        spent = 0.0
    if (located := held.step(lambda: bifurcations(branch))) is None:
        return
    found, took = located
    critical, l1 = None, None
    if spec.from_hopf:  # the normal form decides, as `continue --json` says it
        if (read := held.step(lambda: first_lyapunov(spec.params, spec.name, spec.dt,
                                                     spec.hopf_branch))) is None:
            return
        ly, more = read
        critical, l1, took = ly.criticality, ly.l1, took + more
    if continuations.finish(db, job.id, wid, branch.end, critical, spent + took,
                            [bifurcation_fields(b) for b in found], engine_digest(), l1):
        log.info("continuation %d done: %d points, %s", job.id, len(branch.points),
                 ", ".join(f"{b.type} at {spec.name} = {b.value:.6g}" for b in found)
                 or "no bifurcation")
    else:
        log.warning("continuation %d finished after its lease was lost; discarded", job.id)


class Continuations(JobKind[BranchJob]):
    """Continuations (module docstring)."""

    name = "continuation"
    label = "branch"
    plural = key = "continuations"
    id_key = "continuation_id"
    shown_by = "slopetui branch"
    lease = continuations.lease

    def claim(self, c: Computing) -> BranchJob | None:
        return claim(c.db, c.worker_id)

    def compute(self, c: Computing, job: BranchJob) -> None:
        compute(c.db, c.worker_id, job, c.run, c.control, c.max_attempts)

    def describe(self, db: Database) -> Activity:
        return Activity(continuations.status_counts(db), continuations.held(db))


CONTINUATIONS = Continuations()
