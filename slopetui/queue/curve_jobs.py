"""A curve in two parameters as a job of the queue: submitted, claimed by a worker under a
lease, computed point by point (core.curve_start) with each point saved as soon as it is
known, resumed from the saved points by whoever takes it over, finished with its
codimension-two points.

The policy is the continuations' (slopetui.queue.branch_jobs; the steps' share in
slopetui.queue.thread_steps):

* A worker claims a curve after continuations and hysteresis sweeps and before runs
  (slopetui.queue.registry): it is asked for interactively.
* Each point is saved by the lease holder only, as the next one
  (slopetui.store.jobs.curves.save_point): a killed worker loses at most the point it was
  computing. A fold curve's first point is the slowest (the branch from the Hopf point
  walked to its turn, seconds).
* A stop comes between two points: the curve goes back to the queue with its attempt given
  back; an abort gives it back at once and leaves the point in progress unsaved.
* No fold to start from (OrbitError at the start) is an answer: the job fails at once with
  the reason, no retry. Any other error is retried up to max_attempts.
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
from slopetui.store.jobs import curves
from slopetui.store.jobs.curves import CurveRow, SavedCurvePointRow

if TYPE_CHECKING:  # numpy, scipy and numba: loaded by the worker that computes a curve
    from core.curve_start import CurveSpec, SavedCurvePoint

log = logging.getLogger("slopetui.worker")


@dataclass(frozen=True)
class CurveJob:
    """A claimed curve: what to compute; ``attempts`` counts this one."""

    id: int
    attempts: int
    spec: CurveSpec


def fields_of(spec: CurveSpec) -> dict[str, Any]:
    """The curves row of a spec (queued, with the engine's digest)."""
    return {"kind": spec.start, "param": spec.name, "param2": spec.second,
            **{n: getattr(spec.params, n) for n in PARAM_NAMES}, "dt": spec.dt,
            "end_value": spec.to, "max_points": spec.max_points, "max_step": spec.max_step,
            "hopf_branch": spec.hopf_branch, "branch_end": spec.branch_end,
            "engine": source_digest(), "status": "queued"}


def submit(db: Database, spec: CurveSpec) -> int:
    """Queue a curve; returns its id."""
    return curves.submit(db, fields_of(spec))


def spec_of(row: CurveRow) -> CurveSpec:
    """The spec a curves row asks for, checked: one of stored_inputs.INPUT_ERRORS
    (ParameterError naming the column) for values it cannot be computed from."""
    from core.curve_start import STARTS, CurveSpec
    stored_inputs.present(row, (*PARAM_NAMES, "kind", "param", "param2", "dt", "end_value",
                                "max_points", "max_step", "hopf_branch"))
    params = Params(**{n: getattr(row, n) for n in PARAM_NAMES})
    for column in ("param", "param2"):
        if getattr(row, column) not in PARAM_NAMES:
            raise ParameterError(column, getattr(row, column), f"one of {', '.join(PARAM_NAMES)}")
    if row.kind not in STARTS:
        raise ParameterError("kind", row.kind, " or ".join(STARTS))
    end = check_finite("end_value", row.end_value)
    params.with_(**{row.param2: end})  # raises ParameterError naming the parameter's range
    branch_end = None
    if row.kind in ("pd", "ns"):
        if row.branch_end is None:
            raise ParameterError("branch_end", None, "a value (the store holds NULL)")
        branch_end = check_finite("branch_end", row.branch_end)
    return CurveSpec(params, row.param, row.param2, row.kind,
                     stored_inputs.orbit_step(params, row.dt), end,
                     stored_inputs.whole("max_points", row.max_points, 2),
                     check_positive("max_step", row.max_step),
                     stored_inputs.whole("hopf_branch", row.hopf_branch, 1), branch_end)


def claim(db: Database, worker_id: str) -> CurveJob | None:
    """Claim the oldest queued curve (one attempt charged), or None; one whose stored
    inputs cannot be computed fails at once with the reason, and the next one is
    claimed."""
    return stored_inputs.claim_computable(
        curves, curves.claim, "curve", db, worker_id,
        lambda row: CurveJob(row.id, row.attempts, spec_of(row)))


def point_fields(idx: int, point: SavedCurvePoint) -> dict[str, Any]:
    """The curve_points row of a computed point."""
    m = point.multipliers
    return {"idx": idx, "first": point.first, "second": point.second, "period": point.period,
            "amplitude": point.amplitude, "l1": point.l1, "curvature": point.curvature,
            "multipliers": None if m is None else [[float(x.real), float(x.imag)]
                                                   for x in m.values],
            "flow_index": None if m is None else m.flow_index,
            "translation": None if m is None else float(m.translation),
            "newton_steps": point.newton_steps, "step": point.step,
            "state": None if point.state is None else point.state.astype("<f8").tobytes()}


def saved_of(row: SavedCurvePointRow) -> SavedCurvePoint:
    """A saved point back from its curve_points row."""
    import numpy as np

    from core.curve_start import SavedCurvePoint
    from core.floquet import Multipliers
    m = None
    if row.multipliers is not None:
        values = np.array([complex(re, im) for re, im in row.multipliers])
        m = Multipliers(values, int(row.flow_index or 0), float(row.translation or 1.0))
    state = None if row.state is None else np.frombuffer(row.state, dtype="<f8").copy()
    return SavedCurvePoint(row.first, row.second, row.period, row.amplitude, row.l1,
                           row.curvature, m, row.newton_steps, row.step, state)


def codim2_fields(c: Any) -> dict[str, Any]:
    return {"type": c.type, "first": c.first, "second": c.second, "period": c.period,
            "note": c.note}


def _no_curve(error: BaseException) -> str | None:
    """No fold to start from is an answer, not a crash: recorded at once, no retry."""
    from core.orbit import OrbitError
    return f"no curve: {error}" if isinstance(error, OrbitError) else None


def compute(db: Database, wid: str, job: CurveJob, run: Runner, control: Stops,
            max_attempts: int) -> None:
    """Compute the claimed curve to its end, saving each point (see the module docstring
    for stops, aborts and errors)."""
    from core.curve_start import resume, start
    spec = job.spec
    rows = curves.saved_points(db, job.id)
    try:  # in this thread: a point that cannot be read back would kill the worker
        saved = [saved_of(r) for r in rows]
    except stored_inputs.INPUT_ERRORS as exc:
        stored_inputs.refuse(curves, "curve", db, wid, job.id, ValueError(
            f"a saved point (curve_points) cannot be read back: {exc}"))
        return
    held = HeldJob(db, wid, job.id, job.attempts, "curve", curves, run, control,
                   max_attempts, _no_curve)
    if (begun := held.step(lambda: resume(spec, saved) if saved else start(spec))) is None:
        return
    walk, spent = begun
    log.info("curve %d in (%s, %s): %s (%d saved points)", job.id, spec.name, spec.second,
             "resumed" if saved else "started", len(saved))
    idx = len(saved)
    while True:
        if held.stopped():
            return
        if (stepped := held.step(walk.step)) is None:
            return
        point, took = stepped
        spent += took
        if point is None:
            break
        if not curves.save_point(db, job.id, wid, point_fields(idx, point), spent,
                                 engine_digest()):
            log.warning("curve %d: lease lost; the point is not saved", job.id)
            return
        idx += 1
        spent = 0.0
    if (located := held.step(walk.found)) is None:
        return
    found, took = located
    if curves.finish(db, job.id, wid, walk.end, spent + took,
                     [codim2_fields(c) for c in found], engine_digest()):
        log.info("curve %d done: %d points, %s", job.id, idx,
                 ", ".join(f"{c.type} at {spec.name} = {c.first:.6g}, {spec.second} = "
                           f"{c.second:.6g}" for c in found) or "no codimension-two point")
    else:
        log.warning("curve %d finished after its lease was lost; discarded", job.id)


class Curves(JobKind[CurveJob]):
    """Two-parameter curves (module docstring)."""

    name = "curve"
    label = "curve"
    plural = key = "curves"
    id_key = "curve_id"
    shown_by = "slopetui curve"
    lease = curves.lease

    def claim(self, c: Computing) -> CurveJob | None:
        return claim(c.db, c.worker_id)

    def compute(self, c: Computing, job: CurveJob) -> None:
        compute(c.db, c.worker_id, job, c.run, c.control, c.max_attempts)

    def describe(self, db: Database) -> Activity:
        return Activity(curves.status_counts(db), curves.held(db))


CURVES = Curves()
