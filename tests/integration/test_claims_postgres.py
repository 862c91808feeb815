"""Batch claims take exactly their limit, and only runs of the oldest queued run's tau, on
SQLite and on PostgreSQL.

On PostgreSQL ``UPDATE ... WHERE id IN (SELECT ... LIMIT n FOR UPDATE SKIP LOCKED)`` may
evaluate the sub-select again for each row it updates, and asking for 1 run returned 17
to 43. The claim selects and locks first, in a CTE, and
updates what it picked. The PostgreSQL case is skipped unless $SLOPETUI_TEST_PG names a
server (.ci/run starts one); it makes a database of its own and drops it afterwards.

A batch's runs share tau (the batched kernels' lanes do): the claim reads the settings and
tau of the oldest queued run that no other worker is claiming, locking it as it reads, so
that two workers claiming at once on PostgreSQL each get a batch.
"""

from __future__ import annotations

import os
from collections.abc import Iterator

import pytest
from sqlalchemy import text

from slopetui.queue import jobs
from slopetui.store.database import Database
from slopetui.store.open import open_store
from tests.support import claim_one, pg_database, submit_quick
from tests.unit.test_claims_tau import submit_interleaved

PG_URL = os.environ.get("SLOPETUI_TEST_PG")


@pytest.fixture(params=["sqlite", "postgresql"])
def store(request: pytest.FixtureRequest, tmp_path) -> Iterator[Database]:
    if request.param == "sqlite":
        db = open_store(f"sqlite:///{tmp_path / 'store.db'}")
        yield db
        db.dispose()
        return
    pytest.importorskip("psycopg")
    if not PG_URL:
        pytest.skip("set SLOPETUI_TEST_PG to a PostgreSQL URL")
    with pg_database(PG_URL, f"slopetui_claims_{os.getpid()}") as url:
        db = open_store(url)
        yield db
        db.dispose()


def test_a_batch_claim_takes_exactly_its_limit(store):
    submit_quick(store, 50, method="euler", dt=1e-3)
    taken = [len(jobs.claim_batch(store, f"w{n}", n, {"euler"})) for n in (1, 5, 32)]
    assert taken == [1, 5, 32]
    # and no run went to two workers: 38 held, 12 still queued
    assert len(jobs.claim_batch(store, "w-rest", 50, {"euler"})) == 12
    assert jobs.claim_batch(store, "w-none", 5, {"euler"}) == []


def test_single_claims_take_one_run_each(store):
    submit_quick(store, 3, method="rk4")
    ids = [job.run_id for job in (claim_one(store, f"w{i}") for i in range(3)) if job]
    assert sorted(ids) == [1, 2, 3] and claim_one(store, "w3") is None


def test_a_batch_claim_takes_the_oldest_runs_tau_only(store):
    submit_interleaved(store)  # tau 1, 2, 3, 1, 2, 3, ... in id order, 4 runs each
    claims = [sorted(job.run_id for job in jobs.claim_batch(store, f"w{n}", limit, {"euler"}))
              for n, limit in enumerate((3, 10, 10, 10, 10))]
    assert claims == [[1, 4, 7], [2, 5, 8, 11], [3, 6, 9, 12], [10], []]


def test_a_claim_beside_another_workers_claim_gets_the_next_tau(store):
    """Another worker's claim holds the lock on the oldest queued run (run 1, the only run
    of its tau): this claim reads the next unlocked run's tau and takes its batch, rather
    than run 1's tau, all of whose runs it would skip, and come back with nothing."""
    if store.is_sqlite:
        pytest.skip("SQLite's BEGIN IMMEDIATE serialises claims: no claim runs beside another")
    submit_interleaved(store, n_k=1)                 # tau 1, 2, 3: one run each
    submit_interleaved(store, n_k=2, t_end=30.0)     # then runs 4 to 9: tau 1, 2, 3, 1, 2, 3
    with store.engine.connect() as other:
        assert other.execute(text("SELECT id FROM runs WHERE id = 1 FOR UPDATE")).all() == [(1,)]
        batch = jobs.claim_batch(store, "w", 10, {"euler"})
        other.rollback()
    assert [job.run_id for job in batch] == [2]
    assert [job.run_id for job in jobs.claim_batch(store, "v", 10, {"euler"})] == [1]
