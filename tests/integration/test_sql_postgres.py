"""The read-only query runner on PostgreSQL: statement_timeout, cancel(), streaming.

Skipped unless $SLOPETUI_TEST_PG names a PostgreSQL server (a role that may create
databases: e.g. postgresql+psycopg://postgres@/postgres?host=/tmp/pgsock&port=54329) and
psycopg is installed; .ci/run starts such a throwaway server. The tests make a database of
their own on it and drop it afterwards.
"""

from __future__ import annotations

import os
import threading
import time
from collections.abc import Iterator

import pytest
from sqlalchemy import Engine

from slopetui.store.open import open_store
from slopetui.store.read_query import QueryCancelled, QueryError, QueryTimedOut, ReadQuery
from tests.support import pg_database

PG_URL = os.environ.get("SLOPETUI_TEST_PG")
pytest.importorskip("psycopg")
pytestmark = pytest.mark.skipif(not PG_URL, reason="set SLOPETUI_TEST_PG to a PostgreSQL URL")


@pytest.fixture(scope="module")
def pg_store() -> Iterator[str]:
    """A database of its own on the server (other tests may share the server's)."""
    assert PG_URL is not None  # the module is skipped without it
    with pg_database(PG_URL, f"slopetui_sql_{os.getpid()}") as url:
        yield url


@pytest.fixture
def engine(pg_store: str) -> Iterator[Engine]:
    db = open_store(pg_store)
    engine = db.read_only_engine()
    yield engine
    engine.dispose()
    db.dispose()


def read_all(engine: Engine, query: ReadQuery) -> list[tuple]:
    with query.execute(engine) as rows:
        return [row for chunk in rows.chunks() for row in chunk]


def test_statement_timeout(engine: Engine) -> None:
    start = time.monotonic()
    with pytest.raises(QueryTimedOut, match=r"timed out after 0\.5 s"):
        read_all(engine, ReadQuery("SELECT pg_sleep(30)", timeout_s=0.5))
    assert time.monotonic() - start < 5
    # LOCAL: the pooled connection keeps no limit of ours.
    assert read_all(engine, ReadQuery("SHOW statement_timeout", timeout_s=None)) != \
        [("500ms",)]


def test_cancel_from_another_thread(engine: Engine) -> None:
    query = ReadQuery("SELECT pg_sleep(30)", timeout_s=None)
    threading.Timer(0.3, query.cancel).start()
    start = time.monotonic()
    with pytest.raises(QueryCancelled):
        read_all(engine, query)
    assert time.monotonic() - start < 5
    assert read_all(engine, ReadQuery("SELECT 1")) == [(1,)]


def test_read_only_and_any_statement(engine: Engine) -> None:
    with pytest.raises(QueryError) as caught:
        read_all(engine, ReadQuery("CREATE TABLE slopetui_should_not_exist (x int)"))
    assert caught.value.refused
    assert read_all(engine, ReadQuery("SHOW transaction_read_only")) == [("on",)]
    assert read_all(engine, ReadQuery("EXPLAIN SELECT 1"))  # DECLARE would refuse it


def test_rows_stream_and_a_half_read_result_closes(engine: Engine) -> None:
    query = ReadQuery("SELECT x FROM generate_series(1, 2000) x")
    with query.execute(engine) as rows:
        assert rows.columns == ["x"]
        assert [len(c) for c in rows.chunks(500)] == [500, 500, 500, 500]
    start = time.monotonic()
    endless = ("WITH RECURSIVE c(x) AS (SELECT 1 UNION ALL SELECT x + 1 FROM c) "
               "SELECT x FROM c")
    with ReadQuery(endless).execute(engine) as rows:
        assert rows.fetch(3) == [(1,), (2,), (3,)]
    assert time.monotonic() - start < 5
