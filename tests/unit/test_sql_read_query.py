"""The store's read-only query runner (time limit, cancel, streaming) and the read-only
connection's authorizer, without the CLI or the TUI."""

from __future__ import annotations

import math
import sqlite3
import threading
import time
from collections.abc import Iterator

import pytest
from sqlalchemy import Engine

from slopetui.store import read_query as rq
from slopetui.store.database import Database
from slopetui.store.read_query import (
    QueryCancelled,
    QueryError,
    QueryTimedOut,
    ReadQuery,
    parse_timeout,
)
from tests.support import ENDLESS, SLOW


@pytest.fixture
def engine(db: Database) -> Iterator[Engine]:
    engine = db.read_only_engine()
    yield engine
    engine.dispose()


def read_all(engine: Engine, query: ReadQuery) -> list[tuple]:
    with query.execute(engine) as rows:
        return [row for chunk in rows.chunks() for row in chunk]


def test_rows_come_in_chunks(engine: Engine) -> None:
    query = ReadQuery("WITH RECURSIVE c(x) AS (SELECT 1 UNION ALL SELECT x + 1 FROM c "
                      "WHERE x < 1234) SELECT x, 'a:b' AS s FROM c")
    with query.execute(engine) as rows:
        assert rows.columns == ["x", "s"]
        sizes = [len(chunk) for chunk in rows.chunks(500)]
    assert sizes == [500, 500, 234]
    assert read_all(engine, ReadQuery("SELECT 1 AS one")) == [(1,)]
    with ReadQuery("PRAGMA table_info(runs)").execute(engine) as rows:
        assert rows.columns is not None and rows.fetch()


def test_the_time_limit_stops_a_runaway_query(engine: Engine) -> None:
    start = time.monotonic()
    with pytest.raises(QueryTimedOut, match=r"^timed out after 0\.3 s$") as caught:
        read_all(engine, ReadQuery(SLOW, timeout_s=0.3))
    assert caught.value.timeout_s == 0.3
    assert time.monotonic() - start < 5
    # The connection is usable afterwards, without the old handler.
    assert read_all(engine, ReadQuery("SELECT 2", timeout_s=None)) == [(2,)]


def test_cancel_from_another_thread(engine: Engine) -> None:
    query = ReadQuery(SLOW, timeout_s=None)
    timer = threading.Timer(0.3, query.cancel)
    timer.start()
    start = time.monotonic()
    with pytest.raises(QueryCancelled, match=r"^cancelled$"):
        read_all(engine, query)
    assert 0.25 < time.monotonic() - start < 5
    timer.join()


def test_cancel_before_start_and_between_chunks(engine: Engine) -> None:
    query = ReadQuery("SELECT 1")
    query.cancel()
    with pytest.raises(QueryCancelled):
        read_all(engine, query)
    query = ReadQuery(ENDLESS)
    with pytest.raises(QueryCancelled), query.execute(engine) as rows:
        assert len(rows.fetch(10)) == 10
        query.cancel()  # while the caller is busy with the rows, not in SQLite
        rows.fetch(10)


@pytest.mark.wall_clock  # a starved process spends the 0.5 s limit inside SQLite early
def test_the_limit_counts_database_time_only(engine: Engine) -> None:
    """A reader that takes its time (a pager) does not use up the query's limit."""
    query = ReadQuery(ENDLESS, timeout_s=0.5)
    start = time.monotonic()
    with pytest.raises(QueryTimedOut), query.execute(engine) as rows:
        for _ in range(6):
            assert len(rows.fetch(100)) == 100
            time.sleep(0.15)  # 0.9 s outside SQLite in all: beyond the limit
        while rows.fetch(500):
            pass
    assert time.monotonic() - start > 0.9


def test_errors_are_translated(engine: Engine) -> None:
    with pytest.raises(QueryError) as caught:
        read_all(engine, ReadQuery("SELEC 1"))
    assert caught.value.message == 'near "SELEC": syntax error' and not caught.value.refused
    with pytest.raises(QueryError) as caught:
        read_all(engine, ReadQuery("DELETE FROM runs"))
    assert caught.value.refused
    with ReadQuery("SELECT 1 WHERE 0").execute(engine) as rows:
        assert rows.columns == ["1"] and rows.fetch() == []


def test_the_progress_handler_is_removed_afterwards(engine: Engine) -> None:
    read_all(engine, ReadQuery("SELECT 1", timeout_s=0.5))
    with engine.connect() as conn:
        raw = conn.connection.dbapi_connection
        # Would time out if the last query's handler (deadline long past) were still set.
        time.sleep(0.6)
        assert raw.execute(SLOW.replace("300000000", "100000")).fetchone() == (100000,)


@pytest.mark.parametrize("text,value", [("30", 30.0), ("0.25", 0.25), ("0", None),
                                        ("1e3", 1000.0)])
def test_parse_timeout(text: str, value: float | None) -> None:
    assert parse_timeout(text) == value


@pytest.mark.parametrize("text", ["-1", "nan", "inf", "-inf", "", "abc", "1s"])
def test_parse_timeout_refuses(text: str) -> None:
    with pytest.raises(ValueError, match=r"seconds >= 0 \(0 for no limit\)"):
        parse_timeout(text)


def test_the_limit_must_be_positive() -> None:
    for bad in (0.0, -1.0, math.nan, math.inf):
        with pytest.raises(ValueError):
            ReadQuery("SELECT 1", timeout_s=bad)


def test_progress_interval_is_measured() -> None:
    """The interval is the one the measurement next to it is about."""
    assert rq.PROGRESS_INSTRUCTIONS == 10_000


# -- the authorizer of the read-only connection --------------------------------------------

@pytest.mark.parametrize("sql", ["SELECT fts3_tokenizer('simple')",
                                 "SELECT FTS3_TOKENIZER('porter')",
                                 "SELECT hex(fts3_tokenizer('simple'))",
                                 "SELECT load_extension('/nonexistent')",
                                 "SELECT sqlite_log(1, 'x')",
                                 "SELECT rtreenode(2, x'00')"])
def test_functions_that_leak_or_act_are_refused(engine: Engine, sql: str) -> None:
    with pytest.raises(QueryError) as caught:
        read_all(engine, ReadQuery(sql))
    assert caught.value.refused and "not authorized" in caught.value.message
    with engine.connect() as conn, pytest.raises(Exception, match="not authorized"):
        conn.exec_driver_sql(sql).fetchall()


def test_ordinary_functions_still_run(engine: Engine) -> None:
    sql = ("SELECT abs(-2), round(2.5), json_extract('{\"a\": 3}', '$.a'), "
           "length(randomblob(4)), typeof(sqlite_version()), count(*) FROM runs")
    assert read_all(engine, ReadQuery(sql)) == [(2, 3.0, 3, 4, "text", 0)]


def test_fts3_tokenizer_leaked_an_address_without_the_authorizer() -> None:
    """What the rule is for: a plain connection answers with a pointer."""
    conn = sqlite3.connect(":memory:")
    try:
        value = conn.execute("SELECT fts3_tokenizer('simple')").fetchone()[0]
    except sqlite3.OperationalError:
        pytest.skip("this SQLite is built without FTS3")
    finally:
        conn.close()
    assert isinstance(value, bytes) and len(value) in (4, 8)
