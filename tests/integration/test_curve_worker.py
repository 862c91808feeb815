"""Curves in two parameters computed as jobs: a worker stopped between two points gives the
curve back, another resumes it from the saved points and ends exactly as an uninterrupted
walk would; through real `slopetui worker` pools, a worker killed with SIGKILL mid-curve
and then the whole pool stopped with SIGTERM, the curve is finished once, every point saved
once and in order."""

from __future__ import annotations

import functools
from dataclasses import replace

import numpy as np
import pytest

from core.curve_start import CurveSpec, start
from core.params import Params
from slopetui.queue import curve_jobs
from slopetui.store.jobs import curves
from slopetui.sweeps.curves import curve_of
from tests.integration.pool_support import interrupt_twice_then_finish
from tests.unit.test_branch_jobs import Never, inline

FOLD = CurveSpec(Params(tau=2.0), "k", "tau", "fold", 0.01, 1.5, 6, 0.2)
HOPF = CurveSpec(Params(tau=0.8), "k", "tau", "hopf", 0.01, 0.5, 10, 0.1)
#: The torus of the 2-slip branch (core.torus_continuation): its border holds kappa.
TORUS = CurveSpec(Params(tau=10.0), "k", "tau", "ns", 0.01, 10.4, 5, 0.25, hopf_branch=2,
                  branch_end=25.0)


class StopAfter:
    """The worker's stop sources, saying stop once ``n`` points are saved."""

    def __init__(self, db, cid: int, n: int) -> None:
        self.db, self.cid, self.n = db, cid, n

    def stopping(self) -> bool:
        row = curves.curve(self.db, self.cid)
        return row is not None and row.n_points >= self.n


@functools.cache  # once for both stores
def _uninterrupted(spec: CurveSpec) -> tuple[list[tuple[float, float, float]], list[str]]:
    walk = start(spec)
    points = []
    while (p := walk.step()) is not None:
        points.append((p.first, p.second, p.period))
    return points, [c.type for c in walk.found()]


@pytest.mark.parametrize("spec", [FOLD, HOPF, TORUS], ids=["fold", "hopf", "ns"])
def test_a_stopped_curve_resumes_and_ends_as_an_uninterrupted_one(store, spec):
    reference, found = _uninterrupted(spec)
    cid = curve_jobs.submit(store, spec)
    job = curve_jobs.claim(store, "w1")
    curve_jobs.compute(store, "w1", job, inline, StopAfter(store, cid, 2), max_attempts=3)
    row = curves.curve(store, cid)
    assert (row.status, row.n_points, row.attempts) == ("queued", 2, 0)
    job = curve_jobs.claim(store, "w2")  # another worker takes it over
    curve_jobs.compute(store, "w2", job, inline, Never(), max_attempts=3)
    stored = curve_of(store, cid)
    assert stored is not None and stored.row.status == "done"
    got = [(p["k"], p["tau"], p["period"]) for p in stored.points]
    assert len(got) == len(reference) > 2
    # resumed from the same unknowns, border, secant and step: the same points to rounding
    np.testing.assert_allclose(np.array(got), np.array(reference), rtol=1e-9)
    assert [b["type"] for b in stored.bifurcations] == found
    if spec is HOPF:
        assert found == ["bautin"]


def test_no_fold_to_start_from_fails_at_once_with_the_reason(store):
    # tau = 0.3: the Hopf point is supercritical and its branch in k turns nowhere near
    spec = replace(FOLD, params=Params(tau=0.3), to=0.2, max_points=3)
    cid = curve_jobs.submit(store, spec)
    job = curve_jobs.claim(store, "w1")
    curve_jobs.compute(store, "w1", job, inline, Never(), max_attempts=3)
    row = curves.curve(store, cid)
    assert row.status == "failed" and row.attempts == 1
    assert row.error.startswith("no curve: ")


#: ~0.15 s a point at tau = 10 after a first point of ~4 s; the two interruptions take
#: about ten points (5 saved, then 3 more), so 30 leave twenty to spare.
POOLED = CurveSpec(Params(tau=10.0), "k", "tau", "fold", 0.01, 2.0, 30, 0.05)


def test_a_curve_survives_kill_9_and_a_stop_and_finishes_once(tmp_path, db, db_url):
    cid = curve_jobs.submit(db, POOLED)
    log = tmp_path / "pool.log"
    err = interrupt_twice_then_finish(db_url, log, lambda: curves.curve(db, cid), "n_points",
                                      POOLED.max_points)
    done = curves.curve(db, cid)
    assert done.status == "done" and done.n_points == POOLED.max_points
    assert done.attempts == 2  # the kill cost an attempt; the stop gave its attempt back
    assert [p.idx for p in curves.points(db, cid)] == list(range(POOLED.max_points))
    text = log.read_text()
    assert text.count(f"curve {cid} done") == 1
    assert "died (exit code -9): 1 jobs requeued" in text
    assert text.count("resumed") == 2 and "Traceback" not in text + err
    reference, _ = _uninterrupted(POOLED)
    got = [(p.first, p.second, p.period) for p in curves.points(db, cid)]
    np.testing.assert_allclose(np.array(got), np.array(reference), rtol=1e-9)
