"""`slopetui sql --out FILE` and the console's save (slopetui.sql_files): CSV or JSON by
the extension, the text as stored, NaN as JSON's null, written whole or not at all; a
bad extension, a folder or a failed query write nothing."""

from __future__ import annotations

import csv
import io
import json
import math
import os
from collections.abc import Iterator
from pathlib import Path

import pytest

from slopetui import whole_files
from slopetui.cli import main
from slopetui.sql_files import file_format, save_new_results, save_rows
from slopetui.store.database import Database
from tests.support import SLOW, submit_quick

ROWS = ("SELECT 1 AS n, 'a,b \"q\"' AS label, 0.5 AS x UNION ALL "
        "SELECT 2, char(27) || '[31mred', NULL")


def sql(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str, str]:
    code = main(["sql", *args])
    out = capsys.readouterr()
    return code, out.out, out.err


def test_out_csv_and_json_hold_the_rows_as_stored(db: Database, db_url: str, tmp_path: Path,
                                                  capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = sql(capsys, ROWS, "--out", str(tmp_path / "r.csv"), "--db", db_url)
    assert (code, err) == (0, "") and out == f"2 rows written to {tmp_path / 'r.csv'}\n"
    with (tmp_path / "r.csv").open(newline="") as f:
        assert list(csv.reader(f)) == [["n", "label", "x"], ["1", 'a,b "q"', "0.5"],
                                       ["2", "\x1b[31mred", ""]]
    code, out, _ = sql(capsys, ROWS, "--out", str(tmp_path / "r.JSON"), "--db", db_url)
    assert code == 0 and out.startswith("2 rows written to ")
    assert json.loads((tmp_path / "r.JSON").read_text()) == [
        {"n": 1, "label": 'a,b "q"', "x": 0.5}, {"n": 2, "label": "\x1b[31mred", "x": None}]
    code, _, _ = sql(capsys, "SELECT 1 AS n WHERE 0", "--out", str(tmp_path / "e.json"),
                     "--db", db_url)
    assert code == 0 and json.loads((tmp_path / "e.json").read_text()) == []


def test_out_writes_the_header_of_a_select_without_rows(store_url: str, tmp_path: Path,
                                                        capsys: pytest.CaptureFixture[str]) -> None:
    """No row is still a result: its columns (PostgreSQL's stream forgets them once it
    ends before a first row)."""
    empty = "SELECT id, status AS state FROM runs WHERE id < 0"
    code, out, err = sql(capsys, empty, "--out", str(tmp_path / "e.csv"), "--db", store_url)
    assert (code, err) == (0, "") and out.startswith("0 rows written to ")
    assert (tmp_path / "e.csv").read_text() == "id,state\n"
    code, _, err = sql(capsys, empty, "--out", str(tmp_path / "e.json"), "--db", store_url)
    assert (code, err) == (0, "") and json.loads((tmp_path / "e.json").read_text()) == []
    code, out, _ = sql(capsys, empty, "--csv", "--db", store_url)
    assert (code, out) == (0, "id,state\n")


def test_a_json_column_is_written_to_csv_as_json(store: Database, store_url: str,
                                                 tmp_path: Path,
                                                 capsys: pytest.CaptureFixture[str]) -> None:
    """A sweep's spec is JSON in a CSV cell on both backends (PostgreSQL's driver gives a
    dict, which was written as Python's repr)."""
    sweep = submit_quick(store, 2).sweep_id
    query = f"SELECT spec FROM sweeps WHERE id = {sweep}"
    code, _, err = sql(capsys, query, "--out", str(tmp_path / "s.csv"), "--db", store_url)
    assert (code, err) == (0, "")
    with (tmp_path / "s.csv").open(newline="") as f:
        cell = list(csv.reader(f))[1][0]
    assert json.loads(cell)["x"]["num"] == 2 and json.loads(cell)["fixed"] == {"tau": 2}
    code, out, _ = sql(capsys, query, "--csv", "--db", store_url)
    assert code == 0 and json.loads(list(csv.reader(io.StringIO(out)))[1][0]) == json.loads(cell)


def test_out_keeps_to_the_limit_and_says_so(db: Database, db_url: str, tmp_path: Path,
                                            capsys: pytest.CaptureFixture[str]) -> None:
    many = ("WITH RECURSIVE c(x) AS (SELECT 1 UNION ALL SELECT x + 1 FROM c WHERE x < 50) "
            "SELECT x FROM c")
    code, out, _ = sql(capsys, many, "--out", str(tmp_path / "r.csv"), "--limit", "10",
                       "--db", db_url)
    assert code == 0 and "10 rows written" in out and "more not written, see --limit" in out
    assert len((tmp_path / "r.csv").read_text().splitlines()) == 11
    code, out, _ = sql(capsys, many, "--out", str(tmp_path / "r.csv"), "--limit", "0",
                       "--db", db_url)
    assert code == 0 and out.startswith("50 rows written") and "more" not in out
    code, out, _ = sql(capsys, many.replace("< 50", "< 1500"), "--out", str(tmp_path / "r.csv"),
                       "--db", db_url)  # a file gets every row: no printed table's 1000
    assert code == 0 and out.startswith("1500 rows written") and "more" not in out
    assert len((tmp_path / "r.csv").read_text().splitlines()) == 1501
    code, out, _ = sql(capsys, many.replace("< 50", "< 1500"), "--csv", "--db", db_url)
    assert code == 0 and len(out.splitlines()) == 1001  # printed: 1000 unless --limit


@pytest.mark.parametrize("name", ["r.txt", "r", "r.csv.gz", ".csv"])
def test_another_extension_is_one_line_and_writes_nothing(db: Database, db_url: str,
                                                          tmp_path: Path, name: str,
                                                          capsys: pytest.CaptureFixture[str]) -> None:
    (folder := tmp_path / "out").mkdir()
    code, out, err = sql(capsys, ROWS, "--out", str(folder / name), "--db", db_url)
    assert code == 2 and out == "" and err.count("\n") == 1
    assert err.startswith(f"slopetui sql: error: --out = '{folder / name}': the extension "
                          "names the format: allowed a file name ending in .csv or .json"), err
    assert list(folder.iterdir()) == []


def test_a_failed_query_leaves_no_file_and_the_old_one_as_it_was(
        db: Database, db_url: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (folder := tmp_path / "out").mkdir()
    target = folder / "r.csv"
    target.write_text("old\n")
    code, _, err = sql(capsys, SLOW, "--timeout", "0.3", "--out", str(target), "--db", db_url)
    assert code == 1 and err.startswith("slopetui sql: timed out after 0.3 s")
    assert err.rstrip().endswith("(nothing written)")
    code, _, err = sql(capsys, "SELECT nope FROM runs", "--out", str(target), "--db", db_url)
    assert code == 2 and "no such column" in err
    code, _, err = sql(capsys, "-- nothing", "--out", str(target), "--db", db_url)
    assert code == 2 and err == f"slopetui sql: the statement returns no rows: nothing to " \
                                f"save: {target} not written\n"
    assert target.read_text() == "old\n"
    assert list(folder.iterdir()) == [target]  # no .part left
    (folder / "d.csv").mkdir()
    code, _, err = sql(capsys, ROWS, "--out", str(folder / "d.csv"), "--db", db_url)
    assert code == 2 and "--out: cannot write" in err and "Is a directory" in err
    code, _, err = sql(capsys, ROWS, "--out", str(tmp_path / "no" / "r.csv"), "--db", db_url)
    assert code == 2 and err.startswith("slopetui sql: error: --out: cannot write")


def test_out_and_a_stdout_format_exclude_each_other(db_url: str,
                                                    capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit):
        main(["sql", "SELECT 1", "--csv", "--out", "r.csv", "--db", db_url])
    assert "not allowed with argument" in capsys.readouterr().err


@pytest.mark.parametrize("links", [True, False], ids=["hard links", "no hard links"])
def test_a_new_results_file_never_replaces_one_written_meanwhile(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, links: bool) -> None:
    class Rows(list):  # another save takes sql-results.csv while these rows are written
        def __iter__(self) -> Iterator[tuple[object, ...]]:
            (tmp_path / "sql-results.csv").write_text("the other save's\n")
            return super().__iter__()

    if not links:  # a file system without hard links (FAT, some network mounts)
        def no_link(*args: object) -> None:
            raise PermissionError(1, "Operation not permitted")
        monkeypatch.setattr(os, "link", no_link)
    path, n = save_new_results(tmp_path, "csv", ["n"], Rows([(1,), (2,)]))
    assert (path.name, n) == ("sql-results-2.csv", 2)
    assert path.read_text() == "n\n1\n2\n"
    assert path.stat().st_mode & 0o777 == 0o666 & ~whole_files._umask()  # not mkstemp's 0o600
    assert (tmp_path / "sql-results.csv").read_text() == "the other save's\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["sql-results-2.csv", "sql-results.csv"]


def test_save_rows_writes_what_the_console_holds(tmp_path: Path) -> None:
    rows = [(1, math.nan, "x"), (2, math.inf, None)]
    assert save_rows(tmp_path / "a.json", ["n", "v", "s"], rows) == 2
    assert json.loads((tmp_path / "a.json").read_text()) == [
        {"n": 1, "v": None, "s": "x"}, {"n": 2, "v": None, "s": None}]
    assert save_rows(tmp_path / "a.csv", ["n", "v", "s"], rows) == 2
    assert (tmp_path / "a.csv").read_text() == "n,v,s\n1,nan,x\n2,inf,\n"
    assert file_format("x.Csv") == "csv"
    with pytest.raises(ValueError, match=r"^console = 'x\.tsv': the extension"):
        file_format("x.tsv", "console")
