"""The queue, in one process: claims, leases, attempts, pause/cancel and the cache, on
SQLite and PostgreSQL (``store``)."""

from __future__ import annotations

import math
from datetime import timedelta

from sqlalchemy import func, select, update

from core.point import run_point
from slopetui.queue import jobs, registry
from slopetui.store.models import Run
from slopetui.store.runs import claims
from slopetui.sweeps import control
from tests.support import claim_one, finish_all, submit_quick


def statuses(db, sweep_id):
    with db.sessions() as s:
        return dict(s.execute(select(Run.status, func.count()).where(Run.sweep_id == sweep_id)
                              .group_by(Run.status)).all())


def test_claims_are_unique_and_oldest_first(store):
    sub = submit_quick(store, 4)
    got = [claim_one(store, f"w{i}") for i in range(5)]
    assert [j.run_id for j in got[:4]] == sorted(j.run_id for j in got[:4])
    assert len({j.run_id for j in got[:4]}) == 4 and got[4] is None
    assert statuses(store, sub.sweep_id) == {"running": 4}
    assert got[0].params.tau == 2.0 and got[0].settings.method == "rk4"


def test_a_result_is_written_once_by_the_lease_holder(store):
    submit_quick(store, 1)
    job = claim_one(store, "w1")
    record = run_point(job.params, job.settings).as_record()
    assert jobs.complete(store, job, "w2", record) is False       # not the holder
    assert jobs.complete(store, job, "w1", record) is True
    assert jobs.complete(store, job, "w1", record) is False       # already done
    with store.sessions() as s:
        run = s.get(Run, job.run_id)
        assert run.status == "done" and run.regime == record["regime"]
        assert run.attempts == 1 and run.worker_id == "w1"
        assert run.lambda_max == record["lambda_max"]


def _expire(db, run_id):
    with db.transaction() as s:
        s.execute(update(Run).where(Run.id == run_id)
                  .values(heartbeat_at=db.now(s).replace(year=2000)))


def test_expired_leases_go_back_to_the_queue_and_the_old_holder_is_fenced(store):
    submit_quick(store, 1)
    job = claim_one(store, "dead")
    _expire(store, job.run_id)
    assert registry.requeue_expired(store, lease_s=60) == (1, 0)
    again = claim_one(store, "alive")
    assert again.run_id == job.run_id and again.attempts == 2
    record = run_point(job.params, job.settings).as_record()
    assert jobs.complete(store, job, "dead", record) is False  # woke up too late: fenced off
    assert jobs.complete(store, again, "alive", record) is True


def test_a_fresh_heartbeat_keeps_the_lease(store):
    submit_quick(store, 1)
    assert claim_one(store, "w") is not None
    registry.heartbeat(store, "w")
    assert registry.requeue_expired(store, lease_s=60) == (0, 0)


def test_a_run_fails_after_max_attempts_with_its_error(store):
    submit_quick(store, 1)
    for attempt in (1, 2, 3):
        job = claim_one(store, "w")
        assert job.attempts == attempt
        status = jobs.fail(store, job, "w", f"boom {attempt}", max_attempts=3)
        assert status == ("failed" if attempt == 3 else "queued")
    assert claim_one(store, "w") is None
    with store.sessions() as s:
        run = s.scalars(select(Run)).one()
        assert run.status == "failed" and run.error == "boom 3" and run.finished_at


def test_expired_leases_fail_after_max_attempts(store):
    submit_quick(store, 1)
    for _ in range(2):
        job = claim_one(store, "w")
        _expire(store, job.run_id)
        registry.requeue_expired(store, lease_s=60, max_attempts=2)
    with store.sessions() as s:
        run = s.scalars(select(Run)).one()
    assert run.status == "failed" and "lease expired" in run.error and run.attempts == 2


def test_a_sweep_whose_runs_all_failed_is_failed_not_done(store):
    """Nothing is left to compute in either sweep, but only one has results: the other
    must not read as complete (slopetui status, the application's list)."""
    from slopetui.sweeps.progress import sweep_progress

    failing = submit_quick(store, 2).sweep_id
    while (job := claim_one(store, "w")) is not None:
        jobs.fail(store, job, "w", "boom", max_attempts=1)
    partly = submit_quick(store, 2, tau=3.0).sweep_id
    job = claim_one(store, "w")
    jobs.fail(store, job, "w", "boom", max_attempts=1)
    finish_all(store)
    by_id = {p.id: p for p in sweep_progress(store)}
    assert (by_id[failing].status, by_id[failing].done, by_id[failing].failed) == ("failed", 0, 2)
    assert (by_id[partly].status, by_id[partly].done, by_id[partly].failed) == ("done", 1, 1)
    assert by_id[failing].left == 0 and by_id[failing].eta_s is None


def test_release_does_not_count_an_attempt(store):
    submit_quick(store, 1)
    job = claim_one(store, "w")
    assert jobs.release(store, job, "w")
    assert claim_one(store, "w").attempts == 1


def test_paused_sweeps_are_not_handed_out_and_cancel_cancels_queued_runs(store):
    first = submit_quick(store, 2)
    second = submit_quick(store, 2, tau=3.0)
    assert control.pause(store, first.sweep_id) == "paused"
    assert claim_one(store, "w").sweep_id == second.sweep_id
    assert control.resume(store, first.sweep_id) == control.Resumed("active", 0)
    assert claim_one(store, "w").sweep_id == first.sweep_id
    assert control.cancel(store, first.sweep_id) == 1
    assert statuses(store, first.sweep_id) == {"running": 1, "cancelled": 1}


def test_identical_runs_take_the_cached_result(store):
    first = submit_quick(store, 3)
    finish_all(store)
    again = submit_quick(store, 3)
    assert again.n_cached == 3 and statuses(store, again.sweep_id) == {"done": 3}
    other = submit_quick(store, 3, t_end=300.0)  # another t_end: another result
    assert other.n_cached == 0
    with store.sessions() as s:
        a, b = (list(s.scalars(select(Run).where(Run.sweep_id == i).order_by(Run.ix)))
                for i in (first.sweep_id, again.sweep_id))
    for x, y in zip(a, b, strict=True):
        assert y.cached_from == x.id and y.regime == x.regime
        assert y.lambda_max == x.lambda_max or math.isnan(x.lambda_max)


def test_a_claimed_run_finished_meanwhile_elsewhere_is_served_from_the_cache(store):
    submit_quick(store, 1)
    submit_quick(store, 1)  # the same point, queued before the first finished
    j1, j2 = claim_one(store, "a"), claim_one(store, "b")
    jobs.complete(store, j1, "a", run_point(j1.params, j1.settings).as_record())
    hit = jobs.cached_result(store, j2)
    assert hit is not None and hit[0] == j1.run_id


def test_the_claim_skips_locked_rows_on_postgresql():
    """The SQL the claim sends to PostgreSQL, read without a server (the tests above run
    it on one when $SLOPETUI_TEST_PG names it): the oldest run is read and locked
    skipping locked rows, and the claim stamps database time."""
    from sqlalchemy.dialects import postgresql

    sql = str(claims._OLDEST_SETTINGS.compile(dialect=postgresql.dialect()))
    assert "FOR UPDATE OF runs SKIP LOCKED" in sql
    sql = str(claims._CLAIM_BATCH.compile(dialect=postgresql.dialect()))
    assert "UPDATE runs SET" in sql and "RETURNING runs.id" in sql
    assert "statement_timestamp() AT TIME ZONE 'UTC'" in sql


def test_a_batch_claims_the_oldest_runs_with_the_same_solver_settings(store):
    first = submit_quick(store, 5)                 # rk4, dt 0.01, t_end 200
    other = submit_quick(store, 3, t_end=300.0)    # another t_end: not in the same batch
    later = submit_quick(store, 4)                 # same settings as the first sweep
    batch = jobs.claim_batch(store, "w", 7)
    assert [j.sweep_id for j in batch] == [first.sweep_id] * 5 + [later.sweep_id] * 2
    assert [j.run_id for j in batch] == sorted(j.run_id for j in batch)
    assert len({(j.settings.method, j.settings.dt, j.settings.t_end) for j in batch}) == 1
    assert statuses(store, other.sweep_id) == {"queued": 3}
    with store.sessions() as s:
        held = s.scalars(select(Run).where(Run.worker_id == "w")).all()
    assert {r.id for r in held} == {j.run_id for j in batch}
    # claimed, not started: no attempt charged yet (jobs.begin charges them)
    assert all(r.status == "running" and r.attempts == 0 and r.started_at is None
               for r in held)
    assert not any(j.started for j in batch)
    # the next claim starts from the oldest queued run: the other sweep's settings
    assert {j.sweep_id for j in jobs.claim_batch(store, "v", 7)} == {other.sweep_id}


def test_a_dead_workers_whole_batch_goes_back_to_the_queue_charging_only_started_runs(store):
    sub = submit_quick(store, 6)
    batch = jobs.claim_batch(store, "dead", 4)
    done, computing = jobs.begin(store, batch[:1], "dead")[0], batch[1]
    jobs.complete(store, done, "dead", run_point(done.params, done.settings).as_record())
    assert jobs.begin(store, [computing], "dead")[0].attempts == 1
    # the worker dies in the kernel on batch[1]: batch[2:] were never started
    assert registry.requeue_worker(store, "dead", "worker died") == (3, 0)
    assert statuses(store, sub.sweep_id) == {"done": 1, "queued": 5}
    with store.sessions() as s:
        runs = {r.id: r for r in s.scalars(select(Run))}
    assert runs[computing.run_id].attempts == 1 and runs[computing.run_id].error == "worker died"
    for job in batch[2:]:  # back as they came: no attempt used, no error
        assert runs[job.run_id].attempts == 0 and runs[job.run_id].error is None
    again = jobs.begin(store, jobs.claim_batch(store, "alive", 6), "alive")
    assert {j.run_id for j in again} == set(runs) - {done.run_id}
    assert all(j.attempts == (2 if j.run_id == computing.run_id else 1) for j in again)


def test_begin_charges_an_attempt_once_and_only_to_the_lease_holder(store):
    submit_quick(store, 3)
    batch = jobs.claim_batch(store, "w", 3)
    assert jobs.begin(store, batch, "other") == []               # not the holder
    started = jobs.begin(store, batch[:2], "w")
    assert [(j.attempts, j.started) for j in started] == [(1, True), (1, True)]
    assert jobs.begin(store, started, "w") == started            # already charged: no-op
    with store.sessions() as s:
        assert [r.attempts for r in s.scalars(select(Run).order_by(Run.id))] == [1, 1, 0]


def test_release_gives_back_a_started_runs_attempt_and_leaves_an_unstarted_one(store):
    submit_quick(store, 2)
    first, second = jobs.claim_batch(store, "w", 2)
    first = jobs.begin(store, [first], "w")[0]
    assert jobs.release(store, first, "w") and jobs.release(store, second, "w")
    with store.sessions() as s:
        assert [(r.status, r.attempts) for r in s.scalars(select(Run).order_by(Run.id))] \
            == [("queued", 0), ("queued", 0)]


def test_an_unstarted_run_is_never_failed_by_a_requeue(store):
    """A run held but not started has not used an attempt, whatever max_attempts says."""
    submit_quick(store, 2)
    started, waiting = jobs.claim_batch(store, "dead", 2)
    jobs.begin(store, [started], "dead")
    assert registry.requeue_worker(store, "dead", "died", max_attempts=1) == (1, 1)
    with store.sessions() as s:
        assert s.get(Run, started.run_id).status == "failed"
        assert s.get(Run, waiting.run_id).status == "queued"


def test_a_run_served_from_the_cache_gets_a_start_time(store):
    submit_quick(store, 1)
    finish_all(store)
    submit_quick(store, 1, t_end=300.0)
    job = jobs.claim_batch(store, "w", 1)[0]
    jobs.complete(store, job, "w", run_point(job.params, job.settings).as_record(), cached_from=1)
    with store.sessions() as s:
        run = s.get(Run, job.run_id)
        assert run.status == "done" and run.started_at is not None and run.attempts == 0


def test_a_heartbeat_keeps_every_lease_of_a_batch(store):
    submit_quick(store, 3)
    jobs.claim_batch(store, "w", 3)
    with store.transaction() as s:  # age the leases (by the database's clock, as leases are)
        s.execute(update(Run).values(heartbeat_at=store.now(s) - timedelta(seconds=120)))
    registry.heartbeat(store, "w")
    assert registry.requeue_expired(store, lease_s=60) == (0, 0)


def test_the_batch_claim_skips_locked_rows_on_postgresql():
    from sqlalchemy.dialects import postgresql

    sql = str(claims._CLAIM_BATCH.compile(dialect=postgresql.dialect()))
    assert "FOR UPDATE OF runs SKIP LOCKED" in sql and "LIMIT" in sql
    # locked and picked first, in a CTE; the UPDATE takes what was picked (a sub-select
    # under IN may be evaluated again per row on PostgreSQL: test_claims_postgres.py)
    assert sql.startswith("WITH picked AS") and "UPDATE runs SET" in sql
    assert "FROM picked WHERE runs.id = picked.id" in sql and "RETURNING runs.id" in sql


def test_an_inferred_label_never_serves_as_a_cached_result(store):
    first = submit_quick(store, 1)
    finish_all(store)
    with store.transaction() as s:  # as if adaptive refinement had inferred it
        s.execute(update(Run).where(Run.sweep_id == first.sweep_id).values(inferred=True))
    again = submit_quick(store, 1)
    assert again.n_cached == 0
    job = claim_one(store, "w")
    assert job.sweep_id == again.sweep_id
    assert jobs.cached_result(store, job) is None


def test_runs_computed_one_by_one_are_claimed_one_at_a_time(store):
    """RK4 is computed run by run: a worker holding 32 of them kept idle workers idle."""
    submit_quick(store, 5)  # RK4
    first = jobs.claim_batch(store, "w1", 32, batched={"euler"})
    second = jobs.claim_batch(store, "w2", 32, batched={"euler"})
    assert len(first) == len(second) == 1 and first[0].run_id != second[0].run_id
    assert len(jobs.claim_batch(store, "w3", 32, batched={"rk4"})) == 3  # batched: the rest


def test_a_computed_run_names_the_engine_that_computed_it(store):
    """A run queued by other code (its engine column another digest) and computed here is
    stored with this process's engine, and its cache key follows: a second sweep queued
    here then takes it from the cache. A result served from the cache keeps the run's."""
    from slopetui.queue.cache import cache_key
    first = submit_quick(store, 2)
    with store.sessions() as s, s.begin():
        for run in s.scalars(select(Run).where(Run.sweep_id == first.sweep_id)):
            run.engine = "0123456789abcdef"  # queued by an older engine
            run.cache_key = cache_key({c: getattr(run, c) for c in (
                "a", "b", "c", "d", "k", "v", "tau", "delta", "method", "dt", "t_end", "window",
                "lyap", "history", "stop", "engine")})
    finish_all(store)
    with store.sessions() as s:
        runs = list(s.scalars(select(Run).where(Run.sweep_id == first.sweep_id)))
    assert {r.engine for r in runs} == {jobs.engine_digest()}
    again = submit_quick(store, 2)
    assert again.n_cached == 2
    with store.sessions() as s:
        served = list(s.scalars(select(Run).where(Run.sweep_id == again.sweep_id)))
    assert {r.engine for r in served} == {jobs.engine_digest()}
    assert {r.cache_key for r in served} == {r.cache_key for r in runs}
