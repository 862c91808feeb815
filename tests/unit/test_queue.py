"""The queue, in one process: claims, leases, attempts, pause/cancel and the cache."""

from __future__ import annotations

import math

from sqlalchemy import func, select, update

from core import run_point
from slopetui.queue import jobs
from slopetui.store import claims
from slopetui.store.models import Run
from slopetui.sweeps import control
from tests.support import finish_all, submit_quick


def statuses(db, sweep_id):
    with db.sessions() as s:
        return dict(s.execute(select(Run.status, func.count()).where(Run.sweep_id == sweep_id)
                              .group_by(Run.status)).all())


def test_claims_are_unique_and_oldest_first(db):
    sub = submit_quick(db, 4)
    got = [jobs.claim(db, f"w{i}") for i in range(5)]
    assert [j.run_id for j in got[:4]] == sorted(j.run_id for j in got[:4])
    assert len({j.run_id for j in got[:4]}) == 4 and got[4] is None
    assert statuses(db, sub.sweep_id) == {"running": 4}
    assert got[0].params.tau == 2.0 and got[0].settings.method == "rk4"


def test_a_result_is_written_once_by_the_lease_holder(db):
    submit_quick(db, 1)
    job = jobs.claim(db, "w1")
    record = run_point(job.params, job.settings).as_record()
    assert jobs.complete(db, job, "w2", record) is False          # not the holder
    assert jobs.complete(db, job, "w1", record) is True
    assert jobs.complete(db, job, "w1", record) is False          # already done
    with db.sessions() as s:
        run = s.get(Run, job.run_id)
        assert run.status == "done" and run.regime == record["regime"]
        assert run.attempts == 1 and run.worker_id == "w1"
        assert run.lambda_max == record["lambda_max"]


def _expire(db, run_id):
    with db.transaction() as s:
        s.execute(update(Run).where(Run.id == run_id)
                  .values(heartbeat_at=db.now(s).replace(year=2000)))


def test_expired_leases_go_back_to_the_queue_and_the_old_holder_is_fenced(db):
    submit_quick(db, 1)
    job = jobs.claim(db, "dead")
    _expire(db, job.run_id)
    assert jobs.requeue_expired(db, lease_s=60) == (1, 0)
    again = jobs.claim(db, "alive")
    assert again.run_id == job.run_id and again.attempts == 2
    record = run_point(job.params, job.settings).as_record()
    assert jobs.complete(db, job, "dead", record) is False  # woke up too late: fenced off
    assert jobs.complete(db, again, "alive", record) is True


def test_a_fresh_heartbeat_keeps_the_lease(db):
    submit_quick(db, 1)
    assert jobs.claim(db, "w") is not None
    jobs.heartbeat(db, "w")
    assert jobs.requeue_expired(db, lease_s=60) == (0, 0)


def test_a_run_fails_after_max_attempts_with_its_error(db):
    submit_quick(db, 1)
    for attempt in (1, 2, 3):
        job = jobs.claim(db, "w")
        assert job.attempts == attempt
        status = jobs.fail(db, job, "w", f"boom {attempt}", max_attempts=3)
        assert status == ("failed" if attempt == 3 else "queued")
    assert jobs.claim(db, "w") is None
    with db.sessions() as s:
        run = s.scalars(select(Run)).one()
        assert run.status == "failed" and run.error == "boom 3" and run.finished_at


def test_expired_leases_fail_after_max_attempts(db):
    submit_quick(db, 1)
    for _ in range(2):
        job = jobs.claim(db, "w")
        _expire(db, job.run_id)
        jobs.requeue_expired(db, lease_s=60, max_attempts=2)
    with db.sessions() as s:
        run = s.scalars(select(Run)).one()
    assert run.status == "failed" and "lease expired" in run.error and run.attempts == 2


def test_release_does_not_count_an_attempt(db):
    submit_quick(db, 1)
    job = jobs.claim(db, "w")
    assert jobs.release(db, job, "w")
    assert jobs.claim(db, "w").attempts == 1


def test_paused_sweeps_are_not_handed_out_and_cancel_cancels_queued_runs(db):
    first = submit_quick(db, 2)
    second = submit_quick(db, 2, tau=3.0)
    assert control.pause(db, first.sweep_id) == "paused"
    assert jobs.claim(db, "w").sweep_id == second.sweep_id
    assert control.resume(db, first.sweep_id) == "active"
    assert jobs.claim(db, "w").sweep_id == first.sweep_id
    assert control.cancel(db, first.sweep_id) == 1
    assert statuses(db, first.sweep_id) == {"running": 1, "cancelled": 1}


def test_identical_runs_take_the_cached_result(db):
    first = submit_quick(db, 3)
    finish_all(db)
    again = submit_quick(db, 3)
    assert again.n_cached == 3 and statuses(db, again.sweep_id) == {"done": 3}
    other = submit_quick(db, 3, t_end=300.0)  # another t_end: another result
    assert other.n_cached == 0
    with db.sessions() as s:
        a, b = (list(s.scalars(select(Run).where(Run.sweep_id == i).order_by(Run.ix)))
                for i in (first.sweep_id, again.sweep_id))
    for x, y in zip(a, b, strict=True):
        assert y.cached_from == x.id and y.regime == x.regime
        assert y.lambda_max == x.lambda_max or math.isnan(x.lambda_max)


def test_a_claimed_run_finished_meanwhile_elsewhere_is_served_from_the_cache(db):
    submit_quick(db, 1)
    submit_quick(db, 1)  # the same point, queued before the first finished
    j1, j2 = jobs.claim(db, "a"), jobs.claim(db, "b")
    jobs.complete(db, j1, "a", run_point(j1.params, j1.settings).as_record())
    hit = jobs.cached_result(db, j2)
    assert hit is not None and hit[0] == j1.run_id


def test_the_claim_skips_locked_rows_on_postgresql():
    """No PostgreSQL server here: check the SQL the claim sends to one."""
    from sqlalchemy.dialects import postgresql

    sql = str(claims._CLAIM.compile(dialect=postgresql.dialect()))
    assert "FOR UPDATE OF runs SKIP LOCKED" in sql
    assert sql.startswith("UPDATE runs SET") and "RETURNING runs.id" in sql
    assert "statement_timestamp() AT TIME ZONE 'UTC'" in sql


def test_a_batch_claims_the_oldest_runs_with_the_same_solver_settings(db):
    first = submit_quick(db, 5)                    # rk4, dt 0.01, t_end 200
    other = submit_quick(db, 3, t_end=300.0)       # another t_end: not in the same batch
    later = submit_quick(db, 4)                    # same settings as the first sweep
    batch = jobs.claim_batch(db, "w", 7)
    assert [j.sweep_id for j in batch] == [first.sweep_id] * 5 + [later.sweep_id] * 2
    assert [j.run_id for j in batch] == sorted(j.run_id for j in batch)
    assert len({(j.settings.method, j.settings.dt, j.settings.t_end) for j in batch}) == 1
    assert statuses(db, other.sweep_id) == {"queued": 3}
    with db.sessions() as s:
        held = s.scalars(select(Run).where(Run.worker_id == "w")).all()
    assert {r.id for r in held} == {j.run_id for j in batch}
    # claimed, not started: no attempt charged yet (jobs.begin charges them)
    assert all(r.status == "running" and r.attempts == 0 and r.started_at is None
               for r in held)
    assert not any(j.started for j in batch)
    # the next claim starts from the oldest queued run: the other sweep's settings
    assert {j.sweep_id for j in jobs.claim_batch(db, "v", 7)} == {other.sweep_id}


def test_a_dead_workers_whole_batch_goes_back_to_the_queue_charging_only_started_runs(db):
    sub = submit_quick(db, 6)
    batch = jobs.claim_batch(db, "dead", 4)
    done, computing = jobs.begin(db, batch[:1], "dead")[0], batch[1]
    jobs.complete(db, done, "dead", run_point(done.params, done.settings).as_record())
    assert jobs.begin(db, [computing], "dead")[0].attempts == 1
    # the worker dies in the kernel on batch[1]: batch[2:] were never started
    assert jobs.requeue_worker(db, "dead", "worker died") == (3, 0)
    assert statuses(db, sub.sweep_id) == {"done": 1, "queued": 5}
    with db.sessions() as s:
        runs = {r.id: r for r in s.scalars(select(Run))}
    assert runs[computing.run_id].attempts == 1 and runs[computing.run_id].error == "worker died"
    for job in batch[2:]:  # back as they came: no attempt used, no error
        assert runs[job.run_id].attempts == 0 and runs[job.run_id].error is None
    again = jobs.begin(db, jobs.claim_batch(db, "alive", 6), "alive")
    assert {j.run_id for j in again} == set(runs) - {done.run_id}
    assert all(j.attempts == (2 if j.run_id == computing.run_id else 1) for j in again)


def test_begin_charges_an_attempt_once_and_only_to_the_lease_holder(db):
    submit_quick(db, 3)
    batch = jobs.claim_batch(db, "w", 3)
    assert jobs.begin(db, batch, "other") == []                  # not the holder
    started = jobs.begin(db, batch[:2], "w")
    assert [(j.attempts, j.started) for j in started] == [(1, True), (1, True)]
    assert jobs.begin(db, started, "w") == started               # already charged: no-op
    with db.sessions() as s:
        assert [r.attempts for r in s.scalars(select(Run).order_by(Run.id))] == [1, 1, 0]


def test_release_gives_back_a_started_runs_attempt_and_leaves_an_unstarted_one(db):
    submit_quick(db, 2)
    first, second = jobs.claim_batch(db, "w", 2)
    first = jobs.begin(db, [first], "w")[0]
    assert jobs.release(db, first, "w") and jobs.release(db, second, "w")
    with db.sessions() as s:
        assert [(r.status, r.attempts) for r in s.scalars(select(Run).order_by(Run.id))] \
            == [("queued", 0), ("queued", 0)]


def test_an_unstarted_run_is_never_failed_by_a_requeue(db):
    """A run held but not started has not used an attempt, whatever max_attempts says."""
    submit_quick(db, 2)
    started, waiting = jobs.claim_batch(db, "dead", 2)
    jobs.begin(db, [started], "dead")
    assert jobs.requeue_worker(db, "dead", "died", max_attempts=1) == (1, 1)
    with db.sessions() as s:
        assert s.get(Run, started.run_id).status == "failed"
        assert s.get(Run, waiting.run_id).status == "queued"


def test_a_run_served_from_the_cache_gets_a_start_time(db):
    submit_quick(db, 1)
    finish_all(db)
    submit_quick(db, 1, t_end=300.0)
    job = jobs.claim_batch(db, "w", 1)[0]
    jobs.complete(db, job, "w", run_point(job.params, job.settings).as_record(), cached_from=1)
    with db.sessions() as s:
        run = s.get(Run, job.run_id)
        assert run.status == "done" and run.started_at is not None and run.attempts == 0


def test_a_heartbeat_keeps_every_lease_of_a_batch(db):
    submit_quick(db, 3)
    jobs.claim_batch(db, "w", 3)
    with db.transaction() as s:  # age the leases
        s.execute(update(Run).values(heartbeat_at=func.datetime("now", "-120 seconds")))
    jobs.heartbeat(db, "w")
    assert jobs.requeue_expired(db, lease_s=60) == (0, 0)


def test_the_batch_claim_skips_locked_rows_on_postgresql():
    from sqlalchemy.dialects import postgresql

    sql = str(claims._CLAIM_BATCH.compile(dialect=postgresql.dialect()))
    assert "FOR UPDATE OF runs SKIP LOCKED" in sql and "LIMIT" in sql
    # locked and picked first, in a CTE; the UPDATE takes what was picked (a sub-select
    # under IN may be evaluated again per row on PostgreSQL: test_claims_postgres.py)
    assert sql.startswith("WITH picked AS") and "UPDATE runs SET" in sql
    assert "FROM picked WHERE runs.id = picked.id" in sql and "RETURNING runs.id" in sql


def test_an_inferred_label_never_serves_as_a_cached_result(db):
    first = submit_quick(db, 1)
    finish_all(db)
    with db.transaction() as s:  # as if adaptive refinement had inferred it
        s.execute(update(Run).where(Run.sweep_id == first.sweep_id).values(inferred=True))
    again = submit_quick(db, 1)
    assert again.n_cached == 0
    job = jobs.claim(db, "w")
    assert job.sweep_id == again.sweep_id
    assert jobs.cached_result(db, job) is None


def test_runs_computed_one_by_one_are_claimed_one_at_a_time(db):
    """RK4 is computed run by run: a worker holding 32 of them kept idle workers idle."""
    submit_quick(db, 5)  # RK4
    first = jobs.claim_batch(db, "w1", 32, batched={"euler"})
    second = jobs.claim_batch(db, "w2", 32, batched={"euler"})
    assert len(first) == len(second) == 1 and first[0].run_id != second[0].run_id
    assert len(jobs.claim_batch(db, "w3", 32, batched={"rk4"})) == 3  # batched: the rest
