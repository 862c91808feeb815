"""A hysteresis sweep as a job of the queue: submitted, claimed by a worker under a lease,
computed point by point (core.hysteresis.point) with each point saved as soon as it is
known, with the state it hands over, resumed from the saved points by whoever takes it
over, finished with where each branch changes regime.

The policy is the continuations' (slopetui.queue.branch_jobs; the steps' share in
slopetui.queue.thread_steps):

* Once every point is saved, each branch's transition is refined inside its grid bracket
  (core.hysteresis.refine, from the saved state of the bracket's old end) to the sweep's
  ``tol``, as one more step, and the sweep finished with the refined values and brackets;
  a sweep stopped there refines again when resumed.
* A worker claims a hysteresis sweep after continuations and before runs
  (slopetui.queue.registry): it is asked for interactively.
* The points are numbered along the whole sweep: idx 0 to n - 1 are the up branch at
  ``values[idx]``, n to 2n - 1 the down branch at ``values[2n - 1 - idx]``. Point idx
  starts from the state point idx - 1 handed over (the first from eq. 19): the down
  branch from the up branch's last state, as core.hysteresis.hysteresis does. The state
  is saved to the bit, so a resumed sweep ends exactly as an uninterrupted one.
* Each point is saved by the lease holder only, as the next one
  (slopetui.store.jobs.hysteresis_sweeps.save_point): a killed worker loses at most the point
  it was computing.
* A point whose run leaves the finite range (OrbitError) ends the sweep there, as
  core.hysteresis.branch ends a branch: it is saved as "unstable" with no state (nothing
  to hand over), and the sweep is finished.
* A stop comes between two points: the sweep goes back to the queue with its attempt
  given back; an abort gives it back at once and leaves the point in progress unsaved.
  A sweep that cannot be followed (tau) fails at once with the reason; any other error is
  retried up to max_attempts.
* A row whose stored inputs cannot be computed (a hand-edited store) fails at its claim
  with the reason, and the next one is claimed (slopetui.queue.stored_inputs).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Sequence
from dataclasses import dataclass
from functools import partial
from typing import TYPE_CHECKING, Any

from core.jit_cache import source_digest
from core.params import PARAM_NAMES, ParameterError, Params, check_finite, check_positive
from slopetui.queue import stored_inputs
from slopetui.queue.jobs import engine_digest
from slopetui.queue.kinds import Activity, Computing, JobKind
from slopetui.queue.thread_steps import HeldJob, Runner, Stops
from slopetui.store.database import Database
from slopetui.store.jobs import hysteresis_sweeps
from slopetui.store.jobs.hysteresis_sweeps import HysteresisRow, SavedHysteresisPoint

if TYPE_CHECKING:  # numpy and numba's kernels: loaded by the worker that computes a sweep
    import numpy as np

    from core.hysteresis import Transition, WarmPoint
    from core.orbit import Grid

log = logging.getLogger("slopetui.worker")

#: A relative tolerance at or above this would let a refined transition leave its bracket's
#: scale: the stored tol and ``--tol`` are below it.
TOL_MAX = 0.5


@dataclass(frozen=True)
class HysteresisSpec:
    """What a hysteresis sweep computes (core.hysteresis.hysteresis's arguments): ``name``
    from ``start`` to ``stop`` in ``n_points`` values and back, from ``params``; RK4 step
    ``dt``, ``t_settle`` integrated at each point and its last ``window`` classified
    (model time units); each transition refined to ``tol`` (relative)."""

    params: Params
    name: str
    start: float
    stop: float
    n_points: int
    dt: float
    t_settle: float
    window: float
    #: core.hysteresis.TOL, the default (not imported: it brings numpy to the faces).
    tol: float = 1e-3

    def values(self) -> np.ndarray:
        """The up branch's values (the down branch's reversed)."""
        import numpy as np
        return np.linspace(self.start, self.stop, self.n_points)

    def plan(self, idx: int) -> tuple[str, float]:
        """Point idx of the sweep: its direction and its value."""
        values = self.values()
        n = self.n_points
        return ("up", float(values[idx])) if idx < n else ("down", float(values[2 * n - 1 - idx]))


@dataclass(frozen=True)
class HysteresisJob:
    """A claimed hysteresis sweep: what to compute; ``attempts`` counts this one."""

    id: int
    attempts: int
    spec: HysteresisSpec


def fields_of(spec: HysteresisSpec) -> dict[str, Any]:
    """The hysteresis_sweeps row of a spec (queued, with the engine's digest)."""
    return {"param": spec.name, "start": spec.start, "stop": spec.stop,
            "n_points": spec.n_points, **{n: getattr(spec.params, n) for n in PARAM_NAMES},
            "dt": spec.dt, "t_settle": spec.t_settle, "window": spec.window, "tol": spec.tol,
            "engine": source_digest(), "status": "queued"}


def submit(db: Database, spec: HysteresisSpec) -> int:
    """Queue a hysteresis sweep; returns its id."""
    return hysteresis_sweeps.submit(db, fields_of(spec))


def spec_of(row: HysteresisRow) -> HysteresisSpec:
    """The spec a hysteresis_sweeps row asks for, checked: one of
    stored_inputs.INPUT_ERRORS (ParameterError naming the column) for values it cannot be
    computed from (a sweep along tau is refused later, as an answer: compute)."""
    stored_inputs.present(row, (*PARAM_NAMES, "param", "start", "stop", "n_points", "dt",
                                "t_settle", "window", "tol"))
    params = Params(**{n: getattr(row, n) for n in PARAM_NAMES})
    name = row.param
    if name not in PARAM_NAMES:
        raise ParameterError("param", name, f"one of {', '.join(PARAM_NAMES)}")
    ends = [check_finite(field, getattr(row, field)) for field in ("start", "stop")]
    for value in ends:  # the parameter's own range, as the points will ask it
        params.with_(**{name: value})
    t_settle = check_positive("t_settle", row.t_settle)
    window = check_positive("window", row.window)
    if window > t_settle:
        raise ParameterError("window", window, f"0 < window <= t_settle = {t_settle:g}")
    tol = check_positive("tol", row.tol)
    if tol >= TOL_MAX:
        raise ParameterError("tol", tol, f"0 < tol < {TOL_MAX:g}")
    return HysteresisSpec(params, name, ends[0], ends[1],
                          stored_inputs.whole("n_points", row.n_points, 2),
                          stored_inputs.orbit_step(params, row.dt), t_settle, window, tol)


def claim(db: Database, worker_id: str) -> HysteresisJob | None:
    """Claim the oldest queued hysteresis sweep (one attempt charged), or None; one whose
    stored inputs cannot be computed fails at once with the reason, and the next one is
    claimed."""
    return stored_inputs.claim_computable(
        hysteresis_sweeps, hysteresis_sweeps.claim, "hysteresis sweep", db, worker_id,
        lambda row: HysteresisJob(row.id, row.attempts, spec_of(row)))


def point_fields(idx: int, direction: str, pt: WarmPoint, state: np.ndarray | None
                 ) -> dict[str, Any]:
    """The hysteresis_points row of a point: what the faces read and the state it hands
    over (None: nothing to hand over)."""
    import numpy as np
    return {"idx": idx, "direction": direction, "value": pt.value, "regime": pt.regime,
            "detail": pt.detail, "amplitude": pt.amplitude, "growth": pt.growth,
            "jumped": pt.jumped,
            "state": None if state is None else np.ascontiguousarray(state, "<f8").tobytes()}


def state_of(row: SavedHysteresisPoint, g: Grid) -> np.ndarray:
    """The state a saved point hands over, 5 x (N + 1), back from its bytes (a point that
    hands over none raises TypeError)."""
    import numpy as np
    if row.state is None:
        raise TypeError(f"point {row.idx} hands over no state")
    return np.frombuffer(row.state, dtype="<f8").reshape(5, g.n_delay + 1).copy()


def warm_point(row: SavedHysteresisPoint) -> WarmPoint:
    """A saved point back as core.hysteresis's WarmPoint (NaN where it was)."""
    from core.hysteresis import WarmPoint
    return WarmPoint(row.value, row.regime, row.detail, _nan(row.amplitude),
                     _nan(row.growth), bool(row.jumped))


def _nan(value: float | None) -> float:
    """NaN for None: SQLite stores a NaN as NULL (slopetui.store.models.HysteresisPoint)."""
    return math.nan if value is None else value


def transition_fields(prefix: str, found: Transition | None) -> dict[str, float | None]:
    """A transition as stored (hysteresis_sweeps.TRANSITION_COLUMNS) and read back: ``prefix``
    (onset_up or offset_down) refined, ``prefix_before``/``prefix_after`` its grid bracket;
    all None where the branch keeps its attractor."""
    return {prefix: None if found is None else found.value,
            f"{prefix}_before": None if found is None else found.before,
            f"{prefix}_after": None if found is None else found.after}


def transitions(spec: HysteresisSpec, g: Grid, rows: Sequence[SavedHysteresisPoint]
                ) -> dict[str, float | None]:
    """Each branch's transition refined from the saved points and the states they handed
    over (core.hysteresis.refine), as hysteresis_sweeps.TRANSITION_COLUMNS."""
    from core.hysteresis import refine
    out: dict[str, float | None] = {}
    for direction, name in (("up", "onset_up"), ("down", "offset_down")):
        mine = [r for r in rows if r.direction == direction]
        points = [warm_point(r) for r in mine]
        states = [state_of(r, g) for r in mine if r.state is not None]
        out.update(transition_fields(name, refine(spec.params, spec.name, points, states, g,
                                                  spec.t_settle, spec.window, spec.tol)))
    return out


def _one(spec: HysteresisSpec, g: Grid, idx: int, state: np.ndarray
         ) -> tuple[WarmPoint, np.ndarray | None]:
    """Point idx from ``state``: the point and the state it hands over, or (its run left
    the finite range) an "unstable" point and None, as core.hysteresis.branch records it."""
    from core.hysteresis import WarmPoint, point
    from core.orbit import OrbitError
    _, value = spec.plan(idx)
    try:
        return point(spec.params.with_(**{spec.name: value}), g, state, spec.name,
                     spec.t_settle, spec.window)
    except OrbitError as exc:
        return WarmPoint(value, "unstable", str(exc), math.nan, math.nan), None


def _finish(db: Database, wid: str, job: HysteresisJob, held: HeldJob, g: Grid,
            spent: float) -> None:
    """Refine both transitions (one step: a stop or an abort gives the sweep back) and
    finish the sweep with them."""
    rows = hysteresis_sweeps.saved_points(db, job.id)
    if (stepped := held.step(partial(transitions, job.spec, g, rows))) is None:
        return
    found, took = stepped
    if hysteresis_sweeps.finish(db, job.id, wid, found, spent + took, engine_digest()):
        log.info("hysteresis sweep %d done: %d points, up changes at %s, down at %s", job.id,
                 len(rows), found["onset_up"], found["offset_down"])
    else:
        log.warning("hysteresis sweep %d finished after its lease was lost; discarded", job.id)


def compute(db: Database, wid: str, job: HysteresisJob, run: Runner, control: Stops,
            max_attempts: int) -> None:
    """Compute the claimed sweep to its end, saving each point (see the module docstring
    for the order of the points, stops, aborts and errors)."""
    from core.hysteresis import initial_state
    from core.orbit import Grid
    spec = job.spec
    if spec.name == "tau":  # core.hysteresis.hysteresis refuses it too: an answer, no retry
        hysteresis_sweeps.fail(db, job.id, wid, "no sweep: a hysteresis sweep cannot follow "
                             "tau (the state's history is one delay long)", give_up=True)
        return None
    g = Grid.of(spec.params, spec.dt)
    saved = hysteresis_sweeps.saved_points(db, job.id)
    total = 2 * spec.n_points
    ended = any(r.state is None for r in saved)  # a run left the finite range: the end
    if saved:
        try:  # in this thread: a state that cannot be read back would kill the worker
            state = None if ended else state_of(saved[-1], g)
        except stored_inputs.INPUT_ERRORS as exc:
            stored_inputs.refuse(hysteresis_sweeps, "hysteresis sweep", db, wid, job.id,
                                 ValueError("the state of a saved point (hysteresis_points) "
                                            f"cannot be read back: {exc}"))
            return None
    else:
        _, first = spec.plan(0)
        state = initial_state(spec.params.with_(**{spec.name: first}), g)
    log.info("hysteresis sweep %d in %s: %s (%d saved points)", job.id, spec.name,
             "resumed" if saved else "started", len(saved))
    held = HeldJob(db, wid, job.id, job.attempts, "hysteresis sweep", hysteresis_sweeps, run,
                   control, max_attempts)
    spent = 0.0
    idx = len(saved)
    while state is not None and idx < total:
        if held.stopped():
            return None
        if (stepped := held.step(partial(_one, spec, g, idx, state))) is None:
            return None
        (pt, state), took = stepped
        direction, _ = spec.plan(idx)
        if not hysteresis_sweeps.save_point(db, job.id, wid,
                                          point_fields(idx, direction, pt, state),
                                          spent + took, engine=engine_digest()):
            log.warning("hysteresis sweep %d: lease lost; the point is not saved", job.id)
            return
        spent = 0.0
        idx += 1
    if held.stopped():
        return None
    _finish(db, wid, job, held, g, spent)


class HysteresisSweeps(JobKind[HysteresisJob]):
    """Hysteresis sweeps (module docstring)."""

    name = "hysteresis sweep"
    label = "hysteresis"
    plural = "hysteresis sweeps"
    key = "hysteresis_sweeps"
    id_key = "hysteresis_id"
    shown_by = "slopetui hysteresis --show ID"
    lease = hysteresis_sweeps.lease

    def claim(self, c: Computing) -> HysteresisJob | None:
        return claim(c.db, c.worker_id)

    def compute(self, c: Computing, job: HysteresisJob) -> None:
        compute(c.db, c.worker_id, job, c.run, c.control, c.max_attempts)

    def describe(self, db: Database) -> Activity:
        return Activity(hysteresis_sweeps.status_counts(db), hysteresis_sweeps.held(db))


HYSTERESIS_SWEEPS = HysteresisSweeps()
