"""A queued row whose stored inputs cannot be computed (a hand-edited store) fails at its
claim with the reason naming the field, in one log line without a traceback, and the
claim goes on with the other rows (slopetui.queue.stored_inputs). Until
then such a row raised in the worker's main thread before it was charged an attempt,
killed every worker that claimed it, and stopped the queue for every pool; a NULL in the
batch's settings stalled the claim for ever. On SQLite and PostgreSQL (``store``)."""

from __future__ import annotations

import logging
import re
from collections.abc import Iterator
from typing import Any

import pytest
from sqlalchemy import inspect, select, text, update

from core.branch_start import BranchSpec
from core.params import Params
from slopetui.queue import branch_jobs, hysteresis_jobs, jobs
from slopetui.queue.hysteresis_jobs import HysteresisSpec
from slopetui.store.jobs import continuations, hysteresis_sweeps
from slopetui.store.models import Run
from tests.support import claim_one, submit_quick

#: A state name no store keeps (the history of a run whose state was deleted by hand).
MISSING_STATE = "state:" + "0123456789abcdef"

#: Each kind of poison: the column, the value set by hand (NULL: None), and what the
#: stored error must say, a pattern (submit_quick's runs: RK4, tau = 2, dt = 0.01, t_end =
#: 200). SQLite's RETURNING gives a whole REAL as an integer: "0" or "0.0".
POISONS = [
    pytest.param("k", -1.0, r"k = -1(\.0)? is out of range: allowed k >= 0", id="k-out-of-range"),
    pytest.param("dt", 0.0, r"dt = 0(\.0)? is out of range: allowed dt > 0", id="dt-0"),
    pytest.param("dt", 5.0, r"dt = 5(\.0)? is out of range: allowed 0 < dt <= tau = 2",
                 id="dt-above-tau"),
    pytest.param("t_end", 1e300, r"t_end = 1e\+300 is out of range", id="t_end-beyond-limit"),
    pytest.param("history", "run:999999", "history = 'run:999999' is out of range: allowed "
                 "constant, consistent, or the final state of a stored run",
                 id="history-naming-a-run"),
    pytest.param("history", MISSING_STATE, f"history = '{MISSING_STATE}' is out of range: "
                 r"allowed a final state kept in this store \(initial_states holds none",
                 id="history-state-deleted"),
    pytest.param("method", "\x1b[2J", r"method = '\\x1b\[2J' is out of range: allowed one of",
                 id="method-escape"),
    pytest.param("k", None, r"k = None is out of range: allowed a value \(the store holds NULL\)",
                 id="k-null"),
    pytest.param("dt", None, r"dt = None is out of range: allowed a value \(the store holds "
                 r"NULL\)", id="dt-null"),
]


#: The PostgreSQL columns allow_null dropped the NOT NULL of, put back after each test: the
#: `store` fixture's database is this process's shared one, emptied per test but not
#: rebuilt, and a later test comparing the models with the schema saw the NOT NULLs gone.
_MADE_NULLABLE: list[tuple[Any, str, str]] = []


@pytest.fixture(autouse=True)
def _not_null_again() -> Iterator[None]:
    yield
    while _MADE_NULLABLE:
        db, table, col = _MADE_NULLABLE.pop()
        with db.engine.begin() as conn:
            # (a number: every column a test here empties is one; rows may be referenced)
            conn.exec_driver_sql(f"UPDATE {table} SET {col} = 0 WHERE {col} IS NULL")
            conn.exec_driver_sql(f"ALTER TABLE {table} ALTER COLUMN {col} SET NOT NULL")


def allow_null(db: Any, table: str, column: str, sql_type: str) -> None:
    """Drop the NOT NULL of ``table.column``, keeping its values, as a hand-edited (or
    foreign) schema may have it: PostgreSQL drops the constraint; SQLite, which cannot,
    drops the column and adds it back without it."""
    col = f'"{column}"'  # window is a keyword of PostgreSQL's
    if next(c for c in inspect(db.engine).get_columns(table) if c["name"] == column)["nullable"]:
        # already nullable (continuations.hopf_branch): nothing to drop, and nothing to set
        # back, where setting it back made it NOT NULL for every later test of the process
        return
    with db.engine.begin() as conn:
        if conn.dialect.name == "postgresql":
            conn.exec_driver_sql(f"ALTER TABLE {table} ALTER COLUMN {col} DROP NOT NULL")
            _MADE_NULLABLE.append((db, table, col))
            return
        kept = conn.exec_driver_sql(f"SELECT id, {col} FROM {table}").all()
        conn.exec_driver_sql(f"ALTER TABLE {table} DROP COLUMN {col}")
        conn.exec_driver_sql(f"ALTER TABLE {table} ADD COLUMN {col} {sql_type}")
        for row_id, value in kept:
            conn.execute(text(f"UPDATE {table} SET {col} = :v WHERE id = :id"),
                         {"v": value, "id": row_id})


def poison(db: Any, table: str, row_id: int, column: str, value: Any,
           sql_type: str = "DOUBLE PRECISION") -> None:
    """Set one stored value by hand, as a user with the sqlite3 shell or psql would."""
    if value is None:
        allow_null(db, table, column, sql_type)
    with db.engine.begin() as conn:
        conn.execute(text(f'UPDATE {table} SET "{column}" = :v WHERE id = :id'),
                     {"v": value, "id": row_id})


def run_row(db: Any, run_id: int) -> Run:
    with db.sessions() as s:
        run = s.scalar(select(Run).where(Run.id == run_id))
        assert run is not None
        s.expunge(run)
        return run


def refusals(caplog: pytest.LogCaptureFixture) -> list[logging.LogRecord]:
    return [r for r in caplog.records if "failed at its claim" in r.getMessage()]


@pytest.mark.parametrize(("column", "value", "says"), POISONS)
def test_a_poisoned_run_fails_at_its_claim_and_the_batch_goes_on(store, caplog, column, value,
                                                                 says):
    submit_quick(store, 5)
    poison(store, "runs", 1, column, value)  # the oldest: the claim meets it first
    with caplog.at_level(logging.INFO, logger="slopetui"):
        batch = jobs.claim_batch(store, "w", 10, {"rk4"})
    assert [job.run_id for job in batch] == [2, 3, 4, 5]
    assert jobs.claim_batch(store, "w", 10, {"rk4"}) == []  # the queue holds nothing else
    run = run_row(store, 1)
    assert run.status == "failed" and run.attempts == 0 and run.finished_at is not None
    assert run.error.startswith("not computed: invalid input in the store: ")
    assert re.search(says, run.error), run.error
    [line] = refusals(caplog)
    assert line.getMessage() == f"run 1 failed at its claim: {run.error}"
    assert line.levelno == logging.ERROR and line.exc_info is None  # one line, no traceback
    # and what was claimed computes: begin charges the runs the worker still holds
    assert [job.attempts for job in jobs.begin(store, batch, "w")] == [1, 1, 1, 1]


def test_a_poisoned_run_in_the_middle_of_a_batch_leaves_the_others_claimed(store, caplog):
    submit_quick(store, 5)
    poison(store, "runs", 3, "k", -2.0)  # k is not a batch setting: claimed with the others
    with caplog.at_level(logging.INFO, logger="slopetui"):
        assert [job.run_id for job in jobs.claim_batch(store, "w", 10, {"rk4"})] == [1, 2, 4, 5]
    assert run_row(store, 3).status == "failed"
    assert len(refusals(caplog)) == 1


def test_a_batch_of_poisoned_runs_only_leaves_the_claim_empty_not_stuck(store):
    submit_quick(store, 3)
    for run_id in (1, 2, 3):
        poison(store, "runs", run_id, "dt", 0.0)
    assert jobs.claim_batch(store, "w", 10, {"rk4"}) == []
    with store.sessions() as s:
        assert set(s.scalars(select(Run.status))) == {"failed"}


def test_the_single_claim_fails_a_poisoned_run_and_takes_the_next(store):
    submit_quick(store, 2)
    poison(store, "runs", 1, "dt", 0.0)
    job = claim_one(store, "w")
    assert job is not None and job.run_id == 2
    assert run_row(store, 1).status == "failed" and claim_one(store, "w") is None


def test_a_refused_run_that_the_worker_no_longer_holds_is_left_to_its_holder(store):
    submit_quick(store, 1)
    [job] = jobs.claim_batch(store, "w", 1)
    with store.transaction() as s:  # taken over meanwhile
        s.execute(update(Run).where(Run.id == job.run_id).values(worker_id="other"))
    from slopetui.store.runs import claims
    assert claims.refuse(store, "w", {job.run_id: "not computed"}) == 0
    assert run_row(store, job.run_id).status == "running"


def test_a_state_history_is_read_and_checked_at_the_claim(store):
    from core.point import run_point
    from core.solve import SolverSettings
    from slopetui.sweeps.spec import parse_spec
    from slopetui.sweeps.submit import submit
    from tests.support import QUICK_SOLVER, finish_all
    submit_quick(store, 1)
    finish_all(store)
    spec = parse_spec({"x": {"param": "k", "start": 4, "stop": 8, "num": 2},
                       "fixed": {"tau": 2.0}, "solver": QUICK_SOLVER,
                       "initial": [{"history": "run:1"}]})
    submit(store, spec)
    batch = jobs.claim_batch(store, "w", 10, None)
    assert [job.run_id for job in batch] == [2, 3]
    assert all(job.carried is not None and job.carried.name == job.settings.history
               for job in batch)
    # the carried state is the one the kernel starts from: the result is the run's own
    record = run_point(batch[0].params, batch[0].settings, batch[0].carried).as_record()
    assert isinstance(batch[0].settings, SolverSettings) and record["regime"]


@pytest.mark.parametrize(("column", "value", "says"), [
    ("k", -1.0, r"k = -1(\.0)? is out of range: allowed k >= 0"),
    ("dt", 0.0, r"dt = 0(\.0)? is out of range: allowed dt > 0"),
    ("param", "zz", "param = 'zz' is out of range: allowed one of a, b, c, d, k, v, tau, delta"),
    ("max_points", 0, "max_points = 0 is out of range: allowed an integer >= 1"),
    ("k", None, r"k = None is out of range: allowed a value \(the store holds NULL\)"),
    # a NULL index is no first Hopf point: the row says nothing of where to start
    ("hopf_branch", None, r"hopf_branch = None is out of range: allowed a value"),
    ("hopf_branch", 0, "hopf_branch = 0 is out of range: allowed an integer >= 1"),
], ids=["k-out-of-range", "dt-0", "param", "max_points-0", "k-null", "hopf_branch-null",
        "hopf_branch-0"])
def test_a_poisoned_continuation_fails_at_its_claim_and_the_next_is_claimed(
        store, caplog, column, value, says):
    spec = BranchSpec(Params(tau=2.0), "k", 0.01, from_hopf=True, end=None, max_points=7,
                      max_step=0.5)
    bad, good = branch_jobs.submit(store, spec), branch_jobs.submit(store, spec)
    poison(store, "continuations", bad, column, value,
           "INTEGER" if column in ("max_points", "hopf_branch") else "DOUBLE PRECISION")
    with caplog.at_level(logging.INFO, logger="slopetui"):
        job = branch_jobs.claim(store, "w")
    assert job is not None and job.id == good
    row = continuations.continuation(store, bad)
    assert row is not None and row.status == "failed"
    assert row.error.startswith("not computed: invalid input in the store: ")
    assert re.search(says, row.error), row.error
    [line] = refusals(caplog)
    assert line.getMessage().startswith(f"continuation {bad} failed at its claim: ")
    assert line.exc_info is None
    assert branch_jobs.claim(store, "w") is None


@pytest.mark.parametrize(("column", "value", "says"), [
    ("dt", 0.0, r"dt = 0(\.0)? is out of range: allowed dt > 0"),
    ("dt", 1e-9, r"dt = 1e-09 is out of range: allowed a number in \[tau / 100000, tau\]"),
    ("stop", -3.0, r"k = -3(\.0)? is out of range: allowed k >= 0"),
    ("n_points", 1, r"n_points = 1 is out of range: allowed an integer >= 2"),
    ("tau", 0.0, r"tau = 0(\.0)? is out of range: allowed tau > 0"),
    ("window", None, r"window = None is out of range: allowed a value \(the store holds NULL\)"),
], ids=["dt-0", "dt-tiny", "stop-out-of-range", "n_points-1", "tau-0", "window-null"])
def test_a_poisoned_hysteresis_sweep_fails_at_its_claim_and_the_next_is_claimed(
        store, caplog, column, value, says):
    spec = HysteresisSpec(Params(tau=2.0), "k", 8.0, 12.0, 4, 0.01, 300.0, 100.0)
    bad, good = hysteresis_jobs.submit(store, spec), hysteresis_jobs.submit(store, spec)
    poison(store, "hysteresis_sweeps", bad, column, value,
           "INTEGER" if column == "n_points" else "DOUBLE PRECISION")
    with caplog.at_level(logging.INFO, logger="slopetui"):
        job = hysteresis_jobs.claim(store, "w")
    assert job is not None and job.id == good
    row = hysteresis_sweeps.hysteresis_sweep(store, bad)
    assert row is not None and row.status == "failed"
    assert row.error.startswith("not computed: invalid input in the store: ")
    assert re.search(says, row.error), row.error
    [line] = refusals(caplog)
    assert line.getMessage().startswith(f"hysteresis sweep {bad} failed at its claim: ")
    assert line.exc_info is None
    assert hysteresis_jobs.claim(store, "w") is None


def test_a_continuation_whose_saved_point_cannot_be_read_back_fails_with_the_reason(store,
                                                                                   caplog):
    from tests.unit.test_branch_jobs import SPEC, Never, inline
    from tests.unit.test_branch_jobs import _point as branch_point
    cid = branch_jobs.submit(store, SPEC)
    continuations.claim(store, "w1")
    assert continuations.save_point(store, cid, "w1", {**branch_point(0), "state": b"abc"}, 0.1)
    assert continuations.release(store, cid, "w1")  # then resumed by another worker
    job = branch_jobs.claim(store, "w2")
    assert job is not None
    with caplog.at_level(logging.INFO, logger="slopetui"):
        branch_jobs.compute(store, "w2", job, inline, Never(), max_attempts=3)
    row = continuations.continuation(store, cid)
    assert row is not None and row.status == "failed"
    assert row.error.startswith("not computed: invalid input in the store: a saved point "
                                   "(branch_points) cannot be read back: ")
    [line] = refusals(caplog)
    assert line.exc_info is None


def test_a_hysteresis_sweep_whose_saved_state_cannot_be_read_back_fails_with_the_reason(
        store, caplog):
    from tests.unit.test_branch_jobs import Never, inline
    from tests.unit.test_hysteresis_jobs import SPEC
    from tests.unit.test_hysteresis_jobs import _point as warm_point
    sid = hysteresis_jobs.submit(store, SPEC)
    hysteresis_sweeps.claim(store, "w1")
    assert hysteresis_sweeps.save_point(store, sid, "w1", warm_point(0), 0.1)  # 4 numbers
    assert hysteresis_sweeps.release(store, sid, "w1")
    job = hysteresis_jobs.claim(store, "w2")
    assert job is not None
    with caplog.at_level(logging.INFO, logger="slopetui"):
        hysteresis_jobs.compute(store, "w2", job, inline, Never(), max_attempts=3)
    row = hysteresis_sweeps.hysteresis_sweep(store, sid)
    assert row is not None and row.status == "failed"
    assert row.error.startswith("not computed: invalid input in the store: the state of a "
                                   "saved point (hysteresis_points) cannot be read back: ")
    [line] = refusals(caplog)
    assert line.exc_info is None
