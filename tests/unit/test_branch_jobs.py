"""Continuations as jobs (slopetui.queue.branch_jobs, slopetui.store.jobs.continuations): the lease
guards every write, a stopped branch resumes where it stopped and ends as an uninterrupted
one would, and a branch with no orbit to start from fails at once with the reason."""

from __future__ import annotations

from concurrent.futures import Future
from dataclasses import replace
from typing import Any

import numpy as np
import pytest

from core.branch_start import MIN_STEP, BranchSpec, past_end, resume, start
from core.continuation import bifurcations, step
from core.lyapunov_coefficient import first_lyapunov
from core.params import Params
from slopetui.queue import branch_jobs, registry
from slopetui.store.jobs import continuations
from slopetui.sweeps.branches import branch_of

#: A short delay keeps the state small (N = 200) and a branch quick (~0.05 s a point).
SPEC = BranchSpec(Params(tau=2.0), "k", 0.01, from_hopf=True, end=None, max_points=7,
                  max_step=0.5)


def inline(fn: Any) -> Future[Any]:
    """A Runner that runs the function here (the worker runs it in its compute thread)."""
    future: Future[Any] = Future()
    try:
        future.set_result(fn())
    except BaseException as exc:  # a Future carries any exception
        future.set_exception(exc)
    return future


class StopAfter:
    """The worker's stop sources, saying stop once ``n`` points are saved."""

    def __init__(self, db: Any, cid: int, n: int) -> None:
        self.db, self.cid, self.n = db, cid, n

    def stopping(self) -> bool:
        row = continuations.continuation(self.db, self.cid)
        return row is not None and row.n_points >= self.n


class Never:
    def stopping(self) -> bool:
        return False


def _uninterrupted(spec: BranchSpec) -> list[tuple[float, float, float]]:
    branch, _ = start(spec)
    while step(branch, lambda q: past_end(spec, branch.points[0].value, q), spec.max_points,
               MIN_STEP) is not None:
        pass
    return [(p.value, p.period, p.amplitude) for p in branch.points]


def _point(idx: int) -> dict[str, Any]:
    return {"idx": idx, "value": 1.0 + idx, "period": 10.0, "amplitude": 0.1, "stable": True,
            "unstable_count": 0, "leading_re": 0.5, "leading_im": 0.0,
            "multipliers": [[1.0, 0.0], [0.5, 0.0]], "flow_index": 0, "translation": 1.0,
            "step": 0.1, "state": np.zeros(4).tobytes()}


def test_points_are_saved_by_the_lease_holder_only_and_in_order(store):
    cid = branch_jobs.submit(store, SPEC)
    assert continuations.claim(store, "w1").id == cid
    assert continuations.claim(store, "w2") is None  # one holder
    assert continuations.save_point(store, cid, "w1", _point(0), 0.1)
    assert not continuations.save_point(store, cid, "w1", _point(0), 0.1)  # not the next one
    assert not continuations.save_point(store, cid, "w1", _point(2), 0.1)  # a gap
    assert not continuations.save_point(store, cid, "w2", _point(1), 0.1)  # not the holder
    assert continuations.save_point(store, cid, "w1", _point(1), 0.2)
    row = continuations.continuation(store, cid)
    assert (row.n_points, row.attempts) == (2, 1)
    assert row.runtime_s == pytest.approx(0.3)
    # a shutdown gives it back with its attempt; the points stay
    assert continuations.release(store, cid, "w1")
    assert not continuations.finish(store, cid, "w1", "end", None, 0.0, [])  # no longer held
    row = continuations.continuation(store, cid)
    assert (row.status, row.attempts, row.n_points) == ("queued", 0, 2)
    assert [p.idx for p in continuations.points(store, cid)] == [0, 1]


def test_expired_and_dead_workers_continuations_go_back_or_fail(store):
    first = branch_jobs.submit(store, SPEC)
    second = branch_jobs.submit(store, SPEC)
    continuations.claim(store, "w1")
    continuations.claim(store, "w2")
    assert registry.requeue_worker(store, "w1", "worker died", max_attempts=3) == (1, 0)
    assert continuations.continuation(store, first).status == "queued"
    # max_attempts 1: the second has used its one attempt
    assert registry.requeue_worker(store, "w2", "worker died", max_attempts=1) == (0, 1)
    row = continuations.continuation(store, second)
    assert row.status == "failed" and "gave up after 1 attempts" in row.error
    continuations.claim(store, "w3")
    assert registry.requeue_expired(store, lease_s=3600.0, max_attempts=3) == (0, 0)  # still fresh


# the second Hopf point at tau = 2 is k = 19.97, where a branch of period 1.19 grows
# towards larger k (the first: k = 9.13, period 2.50, towards smaller k)
@pytest.mark.parametrize("hopf_branch", [1, 2])
def test_a_stopped_continuation_resumes_and_ends_as_an_uninterrupted_one(store, hopf_branch):
    spec = replace(SPEC, hopf_branch=hopf_branch)
    reference = _uninterrupted(spec)
    cid = branch_jobs.submit(store, spec)
    job = branch_jobs.claim(store, "w1")
    assert job.spec == spec  # the index too: the queue's worker starts where it was asked
    branch_jobs.compute(store, "w1", job, inline, StopAfter(store, cid, 3), max_attempts=3)
    row = continuations.continuation(store, cid)
    assert (row.status, row.n_points, row.attempts) == ("queued", 3, 0)
    assert row.hopf_value == pytest.approx(reference[0][0], abs=1e-3)
    job = branch_jobs.claim(store, "w2")  # another worker takes it over
    branch_jobs.compute(store, "w2", job, inline, Never(), max_attempts=3)
    stored = branch_of(store, cid)
    assert stored is not None and stored.row.status == "done"
    # the worker reads the criticality from l1, as `continue --json` does: the 2nd Hopf
    # point at tau = 2 is supercritical (l1 = -0.061: its orbits grow towards larger k),
    # which its first orbits, born beside an already unstable rest state, did not say
    local = first_lyapunov(spec.params, "k", spec.dt, hopf_branch)
    assert stored.row.l1 == pytest.approx(local.l1, rel=1e-9)
    assert stored.row.criticality == ("subcritical" if hopf_branch == 1 else "supercritical")
    assert stored.row.hopf_branch == hopf_branch
    got = [(p["value"], p["period"], p["amplitude"]) for p in stored.points]
    assert len(got) == len(reference) == SPEC.max_points
    # the resumed branch predicts from the same y, t and step: the same points to rounding
    np.testing.assert_allclose(np.array(got), np.array(reference), rtol=1e-9, atol=1e-12)


def test_resume_rebuilds_the_branch_a_worker_left(store):
    branch, _ = start(SPEC)
    for _ in range(4):
        step(branch, lambda q: False, 10, MIN_STEP)
    cid = branch_jobs.submit(store, SPEC)
    continuations.claim(store, "w1")
    saved = []
    for i in range(len(branch.points)):
        part = _prefix(branch, i + 1)
        assert continuations.save_point(store, cid, "w1", branch_jobs.point_fields(part), 0.0)
    saved = [branch_jobs.saved_of(r) for r in continuations.saved_points(store, cid)]
    again = resume(SPEC, saved)
    assert again.g0 == branch.g0 and again.h == branch.h
    np.testing.assert_array_equal(again.y, branch.y)
    np.testing.assert_array_equal(again.t, branch.t)
    assert [p.multipliers.unstable_count for p in again.points] == \
        [p.multipliers.unstable_count for p in branch.points]
    # and the bifurcation search reads the rebuilt states as it read the originals
    assert [b.type for b in bifurcations(again)] == [b.type for b in bifurcations(branch)]


def _prefix(branch: Any, n: int) -> Any:
    """A view of ``branch`` as it was with its first n points (step h as saved then)."""
    class View:
        points = branch.points[:n]
        states = branch.states[:n]
        h = branch.h
    return View()


def test_no_orbit_to_start_from_fails_at_once_with_the_reason(store):
    # k = 0.5, tau = 2: a run from eq. 19 comes to rest, so there is no orbit to continue
    spec = BranchSpec(Params(k=0.5, tau=2.0, delta=1e-3), "k", 0.01, from_hopf=False,
                      max_points=5)
    cid = branch_jobs.submit(store, spec)
    job = branch_jobs.claim(store, "w1")
    branch_jobs.compute(store, "w1", job, inline, Never(), max_attempts=3)
    row = continuations.continuation(store, cid)
    assert row.status == "failed" and row.attempts == 1
    assert row.error.startswith("no branch: ")
    assert continuations.points(store, cid) == []


def test_a_computed_continuation_names_the_engine_that_computed_it(store):
    """A continuation queued by other code (its engine column another digest) and computed
    here is stored with this process's engine, as a run is (queue.jobs.complete); finished
    by a worker of another engine than its points', it says "mixed"."""
    from sqlalchemy import update

    from slopetui.queue import jobs
    from slopetui.store.jobs.point_jobs import MIXED_ENGINES
    from slopetui.store.models import Continuation
    cid = branch_jobs.submit(store, SPEC)
    with store.sessions() as s, s.begin():
        s.execute(update(Continuation).where(Continuation.id == cid)
                  .values(engine="0123456789abcdef"))
    job = branch_jobs.claim(store, "w1")
    branch_jobs.compute(store, "w1", job, inline, Never(), 3)
    row = continuations.continuation(store, cid)
    assert row.status == "done" and row.engine == jobs.engine_digest()

    other = branch_jobs.submit(store, SPEC)
    continuations.claim(store, "w1")
    assert continuations.save_point(store, other, "w1", _point(0), 0.1, engine="aaaaaaaaaaaaaaaa")
    assert continuations.finish(store, other, "w1", "end", None, 0.0, [], "bbbbbbbbbbbbbbbb")
    assert continuations.continuation(store, other).engine == MIXED_ENGINES


def test_a_crossing_s_reason_is_stored_and_read_back(store):
    """An undetermined crossing is stored with what decided it (migration 0016's column),
    and `branch --json` reads it back as `continue --json` printed it."""
    from core.continuation import Bifurcation

    cid = branch_jobs.submit(store, SPEC)
    continuations.claim(store, "w1")
    assert continuations.save_point(store, cid, "w1", _point(0), 0.1)
    why = "|mu| - 1 = 3e-7 beyond the circle, within its uncertainty 5e-6"
    found = [Bifurcation("undetermined", 9.03, 5.0, complex(-1.0, 0.0), why),
             Bifurcation("fold", 2.95, 5.5, complex(1.0, 0.0))]
    assert continuations.finish(store, cid, "w1", "end", None, 0.0,
                                [branch_jobs.bifurcation_fields(b) for b in found])
    stored = branch_of(store, cid)
    assert stored is not None
    assert [(b["type"], b["reason"]) for b in stored.bifurcations] == [
        ("undetermined", why), ("fold", "")]
