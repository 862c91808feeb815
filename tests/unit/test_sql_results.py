"""One statement's outcome for the SQL console (sql_results.run_query), without the UI:
done with the raw rows, failed, or halted; never an exception."""

from __future__ import annotations

from collections.abc import Iterator

import pytest
from sqlalchemy import Engine

from slopetui.sql_results import QueryDone, QueryFailed, QueryHalted, run_query
from slopetui.store.database import Database
from slopetui.store.read_query import ReadQuery
from tests.support import SLOW


@pytest.fixture
def engine(db: Database) -> Iterator[Engine]:
    engine = db.read_only_engine()
    yield engine
    engine.dispose()


def numbers(n: int) -> str:
    return (f"WITH RECURSIVE c(x) AS (SELECT 1 UNION ALL SELECT x + 1 FROM c WHERE x < {n}) "
            "SELECT x FROM c")


def test_done_keeps_the_first_rows_raw_and_counts_the_rest(engine: Engine) -> None:
    done = run_query(engine, """SELECT json_extract('{"a":1}', '$.a') AS a, '12:30' AS t""", 10)
    assert isinstance(done, QueryDone)  # the colons are not read as bind parameters
    assert (done.columns, done.rows, done.total) == (["a", "t"], [(1, "12:30")], 1)
    done = run_query(engine, numbers(25), 10)
    assert isinstance(done, QueryDone)
    assert (done.rows, done.total, done.count_stopped) == ([(x,) for x in range(1, 11)], 25,
                                                            None)
    done = run_query(engine, "-- only a comment", 10)
    assert isinstance(done, QueryDone) and not done.returns_rows


def test_failed_and_refused(engine: Engine) -> None:
    failed = run_query(engine, "SELECT 1; SELECT 2", 10)
    assert isinstance(failed, QueryFailed) and not failed.refused
    assert failed.message.startswith("error: ")
    refused = run_query(engine, "DELETE FROM runs", 10)
    assert isinstance(refused, QueryFailed) and refused.refused
    assert refused.message.startswith("refused: the store is opened read-only (")


def test_halted_by_a_cancel_or_the_time_limit(engine: Engine) -> None:
    query = ReadQuery(SLOW)
    query.cancel()
    assert run_query(engine, query, 10) == QueryHalted("cancelled", timed_out=False)
    halted = run_query(engine, ReadQuery(SLOW, 0.2), 10)
    assert isinstance(halted, QueryHalted) and halted.timed_out
    assert halted.reason.startswith("timed out after")
