"""A batch is claimed by tau (store.runs.claims.claim_batch): the batched kernels' lanes share
tau (one delay ring length, one step grid), so a claim takes the oldest queued runs that
share the oldest queued run's solver settings and tau, and a plane whose tau varies
fastest in id order still fills batches, one tau at a time."""

from __future__ import annotations

from sqlalchemy import select

from slopetui.queue import jobs
from slopetui.store.database import Database
from slopetui.store.models import Run
from slopetui.sweeps.spec import parse_spec
from slopetui.sweeps.submit import Submitted, submit

EULER = {"method": "euler", "dt": 1e-3, "t_end": 20.0, "window": 10.0}


def submit_interleaved(db: Database, n_k: int = 4, **solver: object) -> Submitted:
    """A (tau, k) plane whose tau varies fastest: ids 1, 2, 3 have tau 1, 2, 3, id 4 tau 1
    again, and so on (n_k runs per tau)."""
    return submit(db, parse_spec({"x": {"param": "tau", "start": 1, "stop": 3, "num": 3},
                                  "y": {"param": "k", "start": 4, "stop": 12, "num": n_k},
                                  "solver": {**EULER, **solver}}))


def taus_by_id(db: Database) -> dict[int, float]:
    with db.sessions() as s:
        return {run_id: tau for run_id, tau in s.execute(select(Run.id, Run.tau))}


def test_a_batch_takes_only_the_oldest_runs_tau_oldest_first_up_to_the_limit(db):
    submit_interleaved(db)
    tau = taus_by_id(db)
    assert [tau[i] for i in range(1, 7)] == [1.0, 2.0, 3.0, 1.0, 2.0, 3.0]  # interleaved
    claims = [[job.run_id for job in jobs.claim_batch(db, f"w{n}", limit, {"euler"})]
              for n, limit in enumerate((3, 10, 10, 10, 10))]
    # tau 1's oldest three (of four), then all of tau 2 and tau 3 (the oldest queued run
    # is then run 2, then run 3), then tau 1's last one, then nothing
    assert claims == [[1, 4, 7], [2, 5, 8, 11], [3, 6, 9, 12], [10], []]
    for ids in claims[:-1]:
        assert len({tau[i] for i in ids}) == 1
    with db.sessions() as s:  # claimed, not started: no attempt charged
        assert {(r.status, r.attempts, r.started_at) for r in s.scalars(select(Run))} \
            == {("running", 0, None)}


def test_runs_of_the_same_tau_with_other_settings_wait_for_their_own_batch(db):
    first = submit_interleaved(db, n_k=2)
    other = submit_interleaved(db, n_k=2, t_end=30.0)
    batch = jobs.claim_batch(db, "w", 10, {"euler"})
    assert {job.sweep_id for job in batch} == {first.sweep_id}
    assert {job.params.tau for job in batch} == {1.0} and len(batch) == 2
    # every method batched (None): the same grouping
    assert [job.run_id for job in jobs.claim_batch(db, "v", 10, None)] == [2, 5]
    later = jobs.claim_batch(db, "u", 10, {"euler"})
    assert [job.run_id for job in later] == [3, 6]
    assert {job.sweep_id for job in jobs.claim_batch(db, "t", 10, {"euler"})} == {other.sweep_id}


def test_a_method_computed_run_by_run_is_still_claimed_alone(db):
    submit_interleaved(db, n_k=2)
    assert [job.run_id for job in jobs.claim_batch(db, "w", 10, {"rk4"})] == [1]
