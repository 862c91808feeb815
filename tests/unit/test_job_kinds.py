"""The kinds of job (slopetui.queue.registry) and the one lease they are all held under
(slopetui.store.jobs.leases): a worker claims them in the registry's order, one heartbeat and
one requeue serve every kind, and the store reads every job row into a frozen dataclass
of its own, never a SQLAlchemy row."""

from __future__ import annotations

import dataclasses
import json
from datetime import datetime

import pytest
from sqlalchemy import RowMapping, update

from core.params import Params
from slopetui.queue import registry
from slopetui.queue.branch_jobs import submit as submit_branch
from slopetui.queue.curve_jobs import submit as submit_curve
from slopetui.queue.hysteresis_jobs import submit as submit_sweep
from slopetui.queue.kinds import Computing
from slopetui.store.jobs import continuations, curves, hysteresis_sweeps
from slopetui.store.jobs.leases import Lease
from slopetui.store.models import Continuation, Curve, HysteresisSweep, Run, Worker
from slopetui.store.runs import claims
from slopetui.store.workers import register_worker
from tests.support import submit_quick
from tests.unit.test_branch_jobs import SPEC as BRANCH
from tests.unit.test_branch_jobs import _point as branch_point
from tests.unit.test_branch_jobs import inline
from tests.unit.test_curve_jobs import SPEC as CURVE
from tests.unit.test_curve_jobs import _point as curve_point
from tests.unit.test_hysteresis_jobs import SPEC as SWEEP
from tests.unit.test_hysteresis_jobs import _point as sweep_point

#: Long ago: every lease has expired.
LONG_AGO = datetime(2000, 1, 1)


class Never:
    def stopping(self) -> bool:
        return False

    def aborting(self) -> bool:
        return False


def _one_of_each(db) -> tuple[int, int, int]:
    """A queued run, continuation, hysteresis sweep and curve; the continuation's, the
    sweep's and the curve's ids."""
    submit_quick(db, 1)
    return submit_branch(db, BRANCH), submit_sweep(db, SWEEP), submit_curve(db, CURVE)


def test_a_worker_claims_a_continuation_then_a_sweep_then_a_curve_then_runs(store):
    _one_of_each(store)
    c = Computing(store, "w", inline, Never(), max_attempts=3, batch=4, memory_mib=1024)
    claimed = []
    for _ in range(5):
        got = next(((kind.name, job) for kind in registry.KINDS
                    if (job := kind.claim(c)) is not None), None)
        claimed.append(None if got is None else got[0])
    assert claimed == ["continuation", "hysteresis sweep", "curve", "run", None]


def test_one_lease_serves_every_kind(store):
    assert [kind.lease for kind in registry.KINDS] == [continuations.lease,
                                                      hysteresis_sweeps.lease, curves.lease,
                                                      claims.lease]
    assert all(type(kind.lease) is Lease for kind in registry.KINDS)
    cid, sid, curve_id = _one_of_each(store)
    register_worker(store, "w", "h", 1)
    assert continuations.claim(store, "w") and hysteresis_sweeps.claim(store, "w")
    assert curves.claim(store, "w")
    assert len(claims.claim_batch(store, "w", 4, None)) == 1  # held, not started

    def age() -> None:
        with store.transaction() as s:
            for model in (Run, Continuation, HysteresisSweep, Curve):
                s.execute(update(model).values(heartbeat_at=LONG_AGO))

    age()
    registry.heartbeat(store, "w")  # one call extends every kind's lease
    assert registry.requeue_expired(store, lease_s=60.0, max_attempts=3) == (0, 0)
    age()
    assert registry.requeue_expired(store, lease_s=60.0, max_attempts=3) == (4, 0)
    assert continuations.continuation(store, cid).status == "queued"
    assert hysteresis_sweeps.hysteresis_sweep(store, sid).status == "queued"
    assert curves.curve(store, curve_id).status == "queued"

    assert continuations.claim(store, "w") and hysteresis_sweeps.claim(store, "w")
    assert curves.claim(store, "w")
    assert claims.claim_batch(store, "w", 4, None)
    assert registry.requeue_worker(store, "w", "worker died", max_attempts=3) == (4, 0)
    with store.sessions() as s:
        assert s.get(Worker, "w").stopped_at is not None


def _frozen_of_the_store(row: object) -> None:
    assert dataclasses.is_dataclass(row) and not isinstance(row, RowMapping)
    assert not hasattr(row, "__dict__")  # slots
    with pytest.raises(dataclasses.FrozenInstanceError):
        row.id = 0  # type: ignore[misc]


def test_the_store_reads_jobs_into_frozen_dataclasses_of_its_own(store):
    cid, sid, curve_id = _one_of_each(store)
    for row in claims.claim_batch(store, "w", 4, None):
        _frozen_of_the_store(row)
    continuations.claim(store, "w")
    assert continuations.save_point(store, cid, "w", branch_point(0), 0.1)
    assert continuations.finish(store, cid, "w", "end", None, 0.0, [
        {"type": "fold", "value": 1.0, "period": 2.0, "mu_re": 1.0, "mu_im": 0.0}])
    hysteresis_sweeps.claim(store, "w")
    assert hysteresis_sweeps.save_point(store, sid, "w", sweep_point(0), 0.1)
    curves.claim(store, "w")
    assert curves.save_point(store, curve_id, "w", curve_point(0), 0.1)
    assert curves.finish(store, curve_id, "w", "end", 0.0, [
        {"type": "cusp", "first": 1.0, "second": 2.0, "period": 3.0, "note": ""}])
    for row in (continuations.continuation(store, cid), *continuations.continuations(store),
                hysteresis_sweeps.hysteresis_sweep(store, sid),
                *hysteresis_sweeps.hysteresis_sweeps(store), curves.curve(store, curve_id),
                *curves.curves(store)):
        _frozen_of_the_store(row)
    for point in (*continuations.points(store, cid), *continuations.saved_points(store, cid),
                  *continuations.bifurcations(store, cid), *hysteresis_sweeps.points(store, sid),
                  *hysteresis_sweeps.saved_points(store, sid), *curves.points(store, curve_id),
                  *curves.saved_points(store, curve_id), *curves.bifurcations(store, curve_id)):
        assert dataclasses.is_dataclass(point) and not isinstance(point, RowMapping)
        with pytest.raises(dataclasses.FrozenInstanceError):
            point.idx = 0  # type: ignore[misc]
    row = continuations.continuation(store, cid)
    assert (row.status, row.n_points, row.param, row.k) == ("done", 1, "k", Params(tau=2.0).k)
    assert continuations.bifurcations(store, cid)[0].type == "fold"
    assert hysteresis_sweeps.saved_points(store, sid)[0].state == sweep_point(0)["state"]


def test_status_and_workers_print_every_kind_of_the_registry(db, db_url, capsys):
    """What `status` and `workers` print of the kinds other than runs, read through the
    registry: the counts of each kind, and the job each live worker computes."""
    from slopetui.cli import main

    _one_of_each(db)
    submit_branch(db, BRANCH)
    for wid in ("h:1", "h:2", "h:3"):
        register_worker(db, wid, "h", int(wid[-1]))
    continuations.claim(db, "h:1")
    hysteresis_sweeps.claim(db, "h:2")
    assert main(["status", "--json", "--db", db_url]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["continuations"] == {"queued": 1, "running": 1}
    assert out["hysteresis_sweeps"] == {"running": 1}
    assert out["curves"] == {"queued": 1}
    assert [(w["id"], w["continuation_id"], w["hysteresis_id"]) for w in out["workers"]] == [
        ("h:1", 1, None), ("h:2", None, 1), ("h:3", None, None)]
    assert main(["status", "--db", db_url]) == 0
    text = capsys.readouterr().out
    assert "continuations: 1 queued, 1 running (slopetui branch)" in text
    assert "hysteresis sweeps: 1 running (slopetui hysteresis --show ID)" in text
    assert "curves: 1 queued (slopetui curve)" in text
    assert main(["workers", "--db", db_url]) == 0
    doing = [line.split()[2:4] for line in capsys.readouterr().out.splitlines()
             if line.strip().startswith("worker ")]
    assert doing == [["branch", "1"], ["hysteresis", "1"], ["idle", "0"]]
