"""`slopetui sql`: time limit, Ctrl-C, rows streamed rather than held, refused functions."""

from __future__ import annotations

import csv
import io
import json
import os
import signal
import subprocess
import sys
import threading
import time
import tracemalloc
from pathlib import Path

import pytest

from slopetui import sql_results
from slopetui.cli import main
from slopetui.cli import sql as cli_sql
from slopetui.store.open import open_store
from tests.support import ENDLESS, SLOW, new_sqlite_store, submit_quick

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture
def store(db_url: str, sqlite_template: Path) -> str:
    new_sqlite_store(db_url, sqlite_template)
    db = open_store(db_url)
    submit_quick(db, 3)
    db.dispose()
    return db_url


def sql(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str, str]:
    code = main(["sql", *args])
    out = capsys.readouterr()
    return code, out.out, out.err


def numbers(n: int) -> str:
    return (f"WITH RECURSIVE c(x) AS (SELECT 1 UNION ALL SELECT x + 1 FROM c WHERE x < {n}) "
            f"SELECT x, 'row ' || x AS label FROM c")


# -- the time limit ----------------------------------------------------------------------

def test_a_runaway_query_times_out(store: str, capsys: pytest.CaptureFixture[str]) -> None:
    start = time.monotonic()
    code, out, err = sql(capsys, SLOW, "--timeout", "0.5", "--db", store)
    assert time.monotonic() - start < 10
    assert code == 1 and out == ""
    assert err == "slopetui sql: timed out after 0.5 s (--timeout S sets the limit; " \
                  "0 for none)\n"


def test_the_default_limit(store: str, capsys: pytest.CaptureFixture[str],
                           monkeypatch: pytest.MonkeyPatch) -> None:
    assert cli_sql.DEFAULT_TIMEOUT_S == 30
    monkeypatch.setattr(cli_sql, "DEFAULT_TIMEOUT_S", 0.3)
    code, _, err = sql(capsys, SLOW, "--db", store)
    assert code == 1 and "timed out after 0.3 s" in err


@pytest.mark.parametrize("value", ["-1", "nan", "inf", "abc", ""])
def test_a_bad_timeout_is_one_line(store: str, capsys: pytest.CaptureFixture[str],
                                   value: str) -> None:
    code, out, err = sql(capsys, "SELECT 1", "--timeout", value, "--db", store)
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and err.startswith("slopetui sql: error: --timeout must be "
                                                   "a number of seconds >= 0"), err


def test_timeout_zero_means_none(store: str, capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = sql(capsys, "SELECT 42 AS answer", "--timeout", "0", "--db", store)
    assert code == 0 and "42" in out


# -- Ctrl-C --------------------------------------------------------------------------------

#: `slopetui sql` in a child that says on stderr when its query is inside SQLite, so that
#: the test sends SIGINT then (not while the child still imports).
CHILD = """
import sys
from slopetui.cli import main, sql

class Announcing(sql.ReadQuery):
    def _progress(self):
        if not getattr(self, "announced", False):
            self.announced = True
            print("query running", file=sys.stderr, flush=True)
        return super()._progress()

sql.ReadQuery = Announcing
sys.exit(main(sys.argv[1:]))
"""


def test_ctrl_c_cancels_the_query(store: str) -> None:
    child = subprocess.Popen(
        [sys.executable, "-c", CHILD, "sql", SLOW, "--timeout", "0", "--db", store],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT,
        # as from a terminal, whatever this test runner does with SIGINT
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        assert child.stderr is not None
        ready = threading.Event()
        threading.Thread(target=lambda: (child.stderr.readline(), ready.set()),
                         daemon=True).start()
        assert ready.wait(120), "the query never started"
        sent = time.monotonic()
        child.send_signal(signal.SIGINT)
        out, err = child.communicate(timeout=30)
        assert time.monotonic() - sent < 10  # the query itself would take a minute
    finally:
        if child.poll() is None:
            child.kill()
            child.communicate()
    assert child.returncode == 130
    assert out == "" and err == "slopetui sql: interrupted\n"


def test_the_sigint_handler_is_restored(store: str,
                                        capsys: pytest.CaptureFixture[str]) -> None:
    before = signal.getsignal(signal.SIGINT)
    assert sql(capsys, "SELECT 1", "--db", store)[0] == 0
    assert sql(capsys, "SELEC", "--db", store)[0] == 2
    assert signal.getsignal(signal.SIGINT) is before


def test_a_signal_while_running_cancels_in_process(store: str,
                                                    capsys: pytest.CaptureFixture[str]) -> None:
    """The same, through the handler of this process: it only sets the query's flag."""
    started = threading.Event()

    class Announcing(cli_sql.ReadQuery):
        def _progress(self) -> int:
            started.set()
            return super()._progress()

    def interrupt() -> None:
        if started.wait(60):
            os.kill(os.getpid(), signal.SIGINT)

    original = cli_sql.ReadQuery
    cli_sql.ReadQuery = Announcing  # type: ignore[misc]
    killer = threading.Thread(target=interrupt)
    killer.start()
    try:
        start = time.monotonic()
        code, out, err = sql(capsys, SLOW, "--timeout", "0", "--db", store)
    finally:
        cli_sql.ReadQuery = original  # type: ignore[misc]
        killer.join()
    assert (code, out, err) == (130, "", "slopetui sql: interrupted\n")
    assert time.monotonic() - start < 10


# -- streaming -----------------------------------------------------------------------------

def test_rows_are_written_as_they_arrive(store: str,
                                         capsys: pytest.CaptureFixture[str]) -> None:
    """An endless result with --limit 0: rows stream out until the time limit stops it."""
    code, out, err = sql(capsys, ENDLESS, "--limit", "0", "--csv", "--timeout", "0.5",
                         "--db", store)
    assert code == 1 and "timed out after 0.5 s" in err
    rows = list(csv.reader(io.StringIO(out)))
    assert rows[0] == ["x"] and len(rows) > 10_000
    assert [int(r[0]) for r in rows[1:]] == list(range(1, len(rows)))  # no line cut


class LineCounter(io.TextIOBase):
    """A stdout that keeps nothing (capsys would keep the whole output in memory)."""

    def __init__(self) -> None:
        self.lines = 0

    def write(self, text: str) -> int:
        self.lines += text.count("\n")
        return len(text)


def test_limit_zero_does_not_hold_the_result(store: str,
                                             monkeypatch: pytest.MonkeyPatch) -> None:
    n = 30_000
    for fmt in ("--csv", "--json", "--table"):
        sink = LineCounter()
        monkeypatch.setattr(sys, "stdout", sink)
        args = [numbers(n), "--limit", "0", "--db", store]
        if fmt != "--table":
            args.append(fmt)
        tracemalloc.start()
        try:
            code = main(["sql", *args])
            _, peak = tracemalloc.get_traced_memory()
        finally:
            tracemalloc.stop()
        assert code == 0
        assert sink.lines >= n
        # Holding 10^5 rows took 28 MB here (before rows were streamed): these 3 x 10^4,
        # ~8 MB; one chunk, and the first TABLE_WIDTH_ROWS rows of a table, take well
        # under 2 MB. (10^5 rows cost 5 s more under tracemalloc, for no more certainty.)
        assert peak < 2_000_000, (fmt, peak)


@pytest.mark.parametrize("limit", [1, 499, 500, 501, 1000, 1001])
def test_limit_across_chunks(store: str, capsys: pytest.CaptureFixture[str],
                             limit: int) -> None:
    code, out, _ = sql(capsys, numbers(1000), "--limit", str(limit), "--json", "--db", store)
    assert code == 0
    rows = [json.loads(line) for line in out.splitlines()]
    assert [r["x"] for r in rows] == list(range(1, min(limit, 1000) + 1))
    code, out, _ = sql(capsys, numbers(1000), "--limit", str(limit), "--db", store)
    more = "; more not shown, see --limit" if limit < 1000 else ""
    assert out.endswith(f"({min(limit, 1000)} rows{more})\n") or limit == 1
    assert len(out.splitlines()) == min(limit, 1000) + 3


def test_a_long_table_is_aligned_by_its_first_rows(store: str,
                                                   capsys: pytest.CaptureFixture[str],
                                                   monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(cli_sql, "TABLE_WIDTH_ROWS", 5)
    monkeypatch.setattr(sql_results, "FETCH_CHUNK", 4)  # widths over 2 chunks, 8 rows
    code, out, _ = sql(capsys, numbers(12), "--limit", "0", "--db", store)
    assert code == 0
    lines = out.splitlines()
    assert lines[:3] == ["x  label", "-  -----", "1  row 1"]
    assert lines[11] == "10  row 10"  # wider than the measured rows: shifted, not cut
    assert lines[-1] == "(12 rows)"


def test_a_table_stopped_midway_keeps_its_rows(store: str,
                                               capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = sql(capsys, ENDLESS, "--limit", "0", "--timeout", "0.3", "--db", store)
    assert code == 1 and "timed out" in err
    lines = out.splitlines()
    assert lines[0].split() == ["x"] and lines[2].strip() == "1"
    assert not lines[-1].startswith("(")  # no row count: the result is not complete


# -- refused functions ---------------------------------------------------------------------

def test_fts3_tokenizer_is_refused(store: str, capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = sql(capsys, "SELECT fts3_tokenizer('simple')", "--db", store)
    assert code == 2 and out == ""
    assert err == ("slopetui sql: refused: the store is opened read-only "
                   "(not authorized to use function: fts3_tokenizer)\n")
    code, out, _ = sql(capsys, "SELECT hex(zeroblob(2)) AS z", "--db", store)
    assert code == 0 and "0000" in out


def test_a_value_of_a_gigabyte_is_refused_not_built(store, capsys):
    """zeroblob(1e9) is one step for SQLite: no time limit sees it, the length limit does."""
    code, _, err = sql(capsys, "SELECT length(zeroblob(1000000000))", "--db", store)
    assert code == 2 and "too big" in err
    code, out, _ = sql(capsys, "SELECT length(zeroblob(1000))", "--db", store)
    assert code == 0 and "1000" in out


# -- the code shared with the TUI's console (slopetui.sql_results) --------------------------

def test_the_console_reads_rows_as_the_cli_does(store: str) -> None:
    """Both faces run sql_results.fetch: the CLI stops one row past its limit, the console
    also counts the rest."""
    from slopetui.store.read_query import QueryError, ReadQuery

    db = open_store(store)
    engine = db.read_only_engine()
    try:
        chunks: list[list[tuple]] = []
        fetched = sql_results.fetch(engine, ReadQuery(numbers(1200)), chunks.append, 1000)
        assert (fetched.count, fetched.more, fetched.rest) == (1000, True, 0)
        assert sum(map(len, chunks)) == 1000 and chunks[0][0] == (1, "row 1")
        fetched = sql_results.fetch(engine, ReadQuery(numbers(1200)), chunks.append, 1000,
                                    count_rest=True)
        assert (fetched.count, fetched.rest, fetched.count_stopped) == (1000, 200, None)
        fetched = sql_results.fetch(engine, ReadQuery("-- only a comment"), chunks.append, 10)
        assert fetched.columns is None and fetched.count == 0  # no rows at all
        with pytest.raises(QueryError) as raised:
            sql_results.fetch(engine, ReadQuery("DELETE FROM runs"), chunks.append, 10)
        assert sql_results.error_text(raised.value).startswith(
            "refused: the store is opened read-only (")
    finally:
        engine.dispose()
        db.dispose()
    assert [sql_results.cell_text(v) for v in (None, 1 / 3, 42, "a")] == \
        ["NULL", "0.333333", "42", "a"]
