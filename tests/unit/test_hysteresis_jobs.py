"""Hysteresis sweeps as jobs (slopetui.queue.hysteresis_jobs, slopetui.store
.jobs.hysteresis_sweeps): the lease guards every write, a stopped sweep resumes where it stopped
and ends exactly as core.hysteresis.hysteresis run directly, and a run that leaves the
finite range ends the sweep as it ends a branch there."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

import core.hysteresis
from core.hysteresis import WarmPoint, hysteresis
from core.orbit import OrbitError
from core.params import Params
from slopetui.queue import hysteresis_jobs, registry
from slopetui.queue.hysteresis_jobs import HysteresisSpec
from slopetui.queue.registry import backlog
from slopetui.store.jobs import hysteresis_sweeps
from slopetui.store.jobs.point_jobs import MIXED_ENGINES
from slopetui.sweeps.hysteresis_runs import hysteresis_of
from tests.unit.test_branch_jobs import Never, inline

#: A short delay (N = 200) and short points: ~0.25 s for the whole sweep. The up branch
#: rests at k = 8, is kicked off rest at 9.33 (growth > 0) and oscillates from there.
SPEC = HysteresisSpec(Params(tau=2.0), "k", 8.0, 12.0, 4, 0.01, 300.0, 100.0)


class StopAfter:
    """The worker's stop sources, saying stop once ``n`` points are saved."""

    def __init__(self, db: Any, sid: int, n: int) -> None:
        self.db, self.sid, self.n = db, sid, n

    def stopping(self) -> bool:
        row = hysteresis_sweeps.hysteresis_sweep(self.db, self.sid)
        return row is not None and row.n_done >= self.n


def _direct(spec: HysteresisSpec) -> core.hysteresis.Hysteresis:
    return hysteresis(spec.params, spec.name, spec.start, spec.stop, spec.n_points, spec.dt,
                      spec.t_settle, spec.window)


def _key(value: float, regime: str, amplitude: float, growth: float, jumped: bool) -> tuple:
    """A point as a comparable tuple (NaN as None: NaN != NaN)."""
    def nan(x: float) -> float | None:
        return None if math.isnan(x) else x
    return value, regime, nan(amplitude), nan(growth), jumped


def _keys(points: list[WarmPoint]) -> list[tuple]:
    return [_key(p.value, p.regime, p.amplitude, p.growth, p.jumped) for p in points]


def _stored_keys(records: list[dict[str, Any]]) -> list[tuple]:
    return [_key(r["value"], r["regime"], r["amplitude"], r["growth"], r["jumped"])
            for r in records]


def _point(idx: int, direction: str = "up") -> dict[str, Any]:
    return {"idx": idx, "direction": direction, "value": 1.0 + idx, "regime": "sliding",
            "detail": "at rest", "amplitude": math.nan, "growth": -0.1, "jumped": False,
            "state": np.zeros(4).tobytes()}


def _compute(db: Any, wid: str, control: Any = None, max_attempts: int = 3) -> None:
    job = hysteresis_jobs.claim(db, wid)
    assert job is not None
    hysteresis_jobs.compute(db, wid, job, inline, control or Never(), max_attempts)


def test_points_are_saved_by_the_lease_holder_only_and_in_order(store):
    sid = hysteresis_jobs.submit(store, SPEC)
    assert not backlog(store).drained  # a queued sweep keeps --exit-when-idle workers
    assert hysteresis_sweeps.claim(store, "w1").id == sid
    assert hysteresis_sweeps.claim(store, "w2") is None  # one holder
    assert hysteresis_sweeps.save_point(store, sid, "w1", _point(0), 0.1)
    assert not hysteresis_sweeps.save_point(store, sid, "w1", _point(0), 0.1)  # not the next one
    assert not hysteresis_sweeps.save_point(store, sid, "w1", _point(2), 0.1)  # a gap
    assert not hysteresis_sweeps.save_point(store, sid, "w2", _point(1), 0.1)  # not the holder
    assert hysteresis_sweeps.save_point(store, sid, "w1", _point(1), 0.2)
    row = hysteresis_sweeps.hysteresis_sweep(store, sid)
    assert (row.n_done, row.attempts) == (2, 1)
    assert row.runtime_s == pytest.approx(0.3)
    # a shutdown gives it back with its attempt; the points stay
    assert hysteresis_sweeps.release(store, sid, "w1")
    none = dict.fromkeys(hysteresis_sweeps.TRANSITION_COLUMNS)
    assert not hysteresis_sweeps.finish(store, sid, "w1", none, 0.0)  # no longer held
    row = hysteresis_sweeps.hysteresis_sweep(store, sid)
    assert (row.status, row.attempts, row.n_done) == ("queued", 0, 2)
    points = hysteresis_sweeps.points(store, sid)
    assert [p.idx for p in points] == [0, 1] and not hasattr(points[0], "state")
    assert math.isnan(points[0].amplitude)  # NaN survives (SQLite: NULL read back as NaN)


def test_expired_and_dead_workers_sweeps_go_back_or_fail(store):
    first = hysteresis_jobs.submit(store, SPEC)
    second = hysteresis_jobs.submit(store, SPEC)
    hysteresis_sweeps.claim(store, "w1")
    hysteresis_sweeps.claim(store, "w2")
    registry.heartbeat(store, "w1")
    assert registry.requeue_worker(store, "w1", "worker died", max_attempts=3) == (1, 0)
    assert hysteresis_sweeps.hysteresis_sweep(store, first).status == "queued"
    assert registry.requeue_worker(store, "w2", "worker died", max_attempts=1) == (0, 1)
    row = hysteresis_sweeps.hysteresis_sweep(store, second)
    assert row.status == "failed" and "gave up after 1 attempts" in row.error
    hysteresis_sweeps.claim(store, "w3")
    assert registry.requeue_expired(store, lease_s=3600.0, max_attempts=3) == (0, 0)  # still fresh
    assert registry.requeue_expired(store, lease_s=-1.0, max_attempts=3) == (1, 0)  # expired


@pytest.mark.parametrize("stops", [(2,), (4,), (1, 6)])
def test_a_stopped_sweep_resumes_and_ends_as_an_uninterrupted_one(store, stops):
    """Stopped inside the up branch, exactly between the branches (the down branch then
    starts from the saved last up state), and twice."""
    reference = _direct(SPEC)
    assert any(p.jumped for p in reference.up)  # the sweep crosses a kick
    sid = hysteresis_jobs.submit(store, SPEC)
    for i, n in enumerate(stops):
        _compute(store, f"w{i}", StopAfter(store, sid, n))
        row = hysteresis_sweeps.hysteresis_sweep(store, sid)
        assert (row.status, row.n_done, row.attempts) == ("queued", n, 0)
    _compute(store, "last")  # another worker takes it over
    stored = hysteresis_of(store, sid)
    assert stored is not None and stored.row.status == "done"
    assert stored.row.n_done == 2 * SPEC.n_points and stored.row.attempts == 1
    # the state is handed over to the bit: the same points as the direct sweep, exactly
    assert _stored_keys(stored.up) == _keys(reference.up)
    assert _stored_keys(stored.down) == _keys(reference.down)
    assert [p["detail"] for p in stored.points] == \
        [p.detail for p in reference.up + reference.down]
    assert (stored.row.onset_up, stored.row.offset_down) == \
        (reference.onset_up, reference.offset_down)
    assert reference.onset is not None and stored.row.tol == reference.onset.tol
    assert (stored.row.onset_up_before, stored.row.onset_up_after) == \
        (reference.onset.before, reference.onset.after)
    assert backlog(store).drained


def fake_point(p: Params, g: Any, state: np.ndarray, name: str, t_settle: float,
               window: float) -> tuple[WarmPoint, np.ndarray]:
    """At rest below k = 10; from k = 10 the run leaves the finite range."""
    if p.k >= 10.0:
        raise OrbitError("the run left the finite range at t = 12.5")
    return WarmPoint(p.k, "sliding", "at rest", 1e-6, -0.01), state + 1.0


def test_a_run_leaving_the_finite_range_ends_the_sweep_as_it_ends_a_branch(store, monkeypatch):
    monkeypatch.setattr(core.hysteresis, "point", fake_point)
    spec = HysteresisSpec(Params(tau=2.0), "k", 8.0, 12.0, 3, 0.01, 300.0, 100.0)
    reference = _direct(spec)
    assert reference.down == [] and reference.up[-1].regime == "unstable"
    sid = hysteresis_jobs.submit(store, spec)
    _compute(store, "w1")
    stored = hysteresis_of(store, sid)
    assert stored is not None and stored.row.status == "done" and stored.row.error is None
    assert _stored_keys(stored.up) == _keys(reference.up) and stored.down == []
    assert stored.up[-1]["detail"] == "the run left the finite range at t = 12.5"
    # the bracket is the grid's; the refined value lies in it (the state of k = 8 carried)
    assert reference.onset is not None and (reference.onset.before, reference.onset.after) == \
        (stored.row.onset_up_before, stored.row.onset_up_after) == (8.0, 10.0)
    assert stored.row.onset_up == reference.onset_up and 8.0 < reference.onset.value < 10.0
    assert hysteresis_sweeps.saved_points(store, sid)[-1].state is None  # nothing handed over


def test_a_sweep_killed_after_its_last_point_is_only_finished(store, monkeypatch):
    """The worker died between saving the point that ended the sweep and finishing it:
    the next one computes no point more, only the refinement inside the bracket (8, 10),
    from the saved state of k = 8."""
    monkeypatch.setattr(core.hysteresis, "point", fake_point)
    spec = HysteresisSpec(Params(tau=2.0), "k", 8.0, 12.0, 3, 0.01, 300.0, 100.0)
    sid = hysteresis_jobs.submit(store, spec)
    hysteresis_sweeps.claim(store, "w1")
    fields = [hysteresis_jobs.point_fields(0, "up", WarmPoint(8.0, "sliding", "", 0.0, -1.0),
                                           np.zeros((5, 201))),
              hysteresis_jobs.point_fields(1, "up", WarmPoint(10.0, "unstable", "gone",
                                                              math.nan, math.nan), None)]
    for f in fields:
        assert hysteresis_sweeps.save_point(store, sid, "w1", f, 0.0)
    registry.requeue_worker(store, "w1", "worker died", max_attempts=3)
    monkeypatch.setattr(core.hysteresis, "point", None)  # computing anything would raise
    _compute(store, "w2")
    row = hysteresis_sweeps.hysteresis_sweep(store, sid)
    assert (row.status, row.n_done) == ("done", 2)
    assert (row.onset_up_before, row.onset_up_after) == (8.0, 10.0)
    assert 8.0 < row.onset_up < 10.0


def test_errors_are_retried_and_tau_fails_at_once(store, monkeypatch):
    def broken(*args: Any) -> Any:
        raise RuntimeError("a bug")
    monkeypatch.setattr(core.hysteresis, "point", broken)
    sid = hysteresis_jobs.submit(store, SPEC)
    _compute(store, "w1", max_attempts=2)
    row = hysteresis_sweeps.hysteresis_sweep(store, sid)
    assert row.status == "queued" and "RuntimeError: a bug" in row.error
    _compute(store, "w2", max_attempts=2)
    assert hysteresis_sweeps.hysteresis_sweep(store, sid).status == "failed"
    tau = hysteresis_jobs.submit(store, HysteresisSpec(Params(), "tau", 1.0, 2.0, 3, 0.01,
                                                    300.0, 100.0))
    _compute(store, "w3")
    row = hysteresis_sweeps.hysteresis_sweep(store, tau)
    assert row.status == "failed" and row.attempts == 1
    assert row.error.startswith("no sweep: ") and "tau" in row.error


def _queued_by_older_engine(db: Any, sid: int) -> None:
    from sqlalchemy import update

    from slopetui.store.models import HysteresisSweep
    with db.sessions() as s, s.begin():
        s.execute(update(HysteresisSweep).where(HysteresisSweep.id == sid)
                  .values(engine="0123456789abcdef"))


def test_a_computed_sweep_names_the_engine_that_computed_it(store):
    """A sweep queued by other code (its engine column another digest) and computed here
    is stored with this process's engine, as a run is (queue.jobs.complete)."""
    from slopetui.queue import jobs
    sid = hysteresis_jobs.submit(store, SPEC)
    _queued_by_older_engine(store, sid)
    _compute(store, "w1")
    row = hysteresis_sweeps.hysteresis_sweep(store, sid)
    assert row.status == "done" and row.engine == jobs.engine_digest()


def test_a_sweep_resumed_by_a_worker_of_another_engine_says_mixed(store):
    sid = hysteresis_jobs.submit(store, SPEC)
    hysteresis_sweeps.claim(store, "w1")
    assert hysteresis_sweeps.save_point(store, sid, "w1", _point(0), 0.1, engine="aaaaaaaaaaaaaaaa")
    assert hysteresis_sweeps.hysteresis_sweep(store, sid).engine == "aaaaaaaaaaaaaaaa"
    assert hysteresis_sweeps.save_point(store, sid, "w1", _point(1), 0.1, engine="aaaaaaaaaaaaaaaa")
    assert hysteresis_sweeps.release(store, sid, "w1")
    hysteresis_sweeps.claim(store, "w2")
    assert hysteresis_sweeps.save_point(store, sid, "w2", _point(2), 0.1, engine="bbbbbbbbbbbbbbbb")
    assert hysteresis_sweeps.hysteresis_sweep(store, sid).engine == MIXED_ENGINES
    none = dict.fromkeys(hysteresis_sweeps.TRANSITION_COLUMNS)
    assert hysteresis_sweeps.finish(store, sid, "w2", none, 0.0, "bbbbbbbbbbbbbbbb")
    assert hysteresis_sweeps.hysteresis_sweep(store, sid).engine == MIXED_ENGINES
