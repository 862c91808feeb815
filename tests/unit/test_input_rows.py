"""Bad input that ended in a traceback or exited 0, row by row: each is
now one line on stderr naming the field and what is allowed, exit status 2, and nothing
written (no store created, no default store, no figure). The numpy bool of `run --json`
is tests/unit/test_json_text.py's."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from slopetui.cli import main
from tests.support import submit_quick


@pytest.fixture(autouse=True)
def private_home(tmp_path, monkeypatch):
    """The default store and pool files in the test's folder, to see that none appears
    (platformdirs reads XDG_* at each call); no $SLOPETUI_DB."""
    monkeypatch.setenv("XDG_DATA_HOME", str(tmp_path / "data"))
    monkeypatch.setenv("XDG_STATE_HOME", str(tmp_path / "state"))
    monkeypatch.delenv("SLOPETUI_DB", raising=False)
    monkeypatch.chdir(tmp_path)


def one_line(capsys, command: str, field: str) -> str:
    """The one line of a refusal: it names the field; nothing on stdout, no traceback."""
    captured = capsys.readouterr()
    lines = captured.err.splitlines()
    assert captured.out == "" and len(lines) == 1, captured.err
    assert lines[0].startswith(f"slopetui {command}: error: {field}"), lines[0]
    return lines[0]


def nothing_created(tmp_path: Path, *keep: str) -> None:
    """No store, default store, log, figure or pool file appeared in the test's folder."""
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(keep)


def test_a_history_run_id_beyond_sql_integers(tmp_path, capsys):
    """Before: OverflowError from the SQLite driver, after the store was created."""
    store = tmp_path / "s.db"
    for text in ("run:999999999999999999999999", "run:0", "run:²"):
        assert main(["run", "--history", text, "--t-end", "100", "--db", f"sqlite:///{store}"]) == 2
        line = one_line(capsys, "run", "history = ")
        assert "allowed" in line and ("9223372036854775807" in line or "run:ID" in line)
    nothing_created(tmp_path)


@pytest.mark.parametrize("text", ["-5", "inf", "-inf", "nan", "1e-9", "x", "", "1e12"])
def test_orbit_seed_length_out_of_range(capsys, tmp_path, text):
    """Before: -5 a ValueError (an empty window), inf an OverflowError."""
    assert main(["orbit", "--t-seed", text]) == 2
    assert "allowed a number from 100 to 500000" in one_line(capsys, "orbit", "t-seed = ")
    nothing_created(tmp_path)


def test_orbit_seed_of_more_steps_than_memory(capsys):
    """A tiny delay allows a tiny step, and 4 tau + 600 of it did not fit in memory."""
    assert main(["orbit", "--tau", "0.001", "--dt", "1e-8"]) == 2
    assert "held in memory" in one_line(capsys, "orbit", "dt = ")


@pytest.mark.parametrize("url", ["postgresql://u@[::1:5432/x", "postgresql://u@host:port/x"])
def test_a_url_sqlalchemy_misreads(capsys, tmp_path, url):
    """Before: ValueError "invalid literal for int() with base 10" from make_url."""
    assert main(["status", "--db", url]) == 2
    assert "is not a SQLAlchemy database URL" in one_line(capsys, "status", "--db")
    nothing_created(tmp_path)


@pytest.mark.parametrize("command", [["status"], ["status", "--json"], ["runs"], ["export", "1", "--json"],
                                     ["sql", "select 1"], ["run", "--history", "run:1"]])
def test_an_empty_db_is_refused_not_read_as_the_default(capsys, tmp_path, command):
    """Before: exit 0, and the default store created (or read)."""
    assert main([*command, "--db", ""]) == 2
    assert "allowed a SQLAlchemy URL" in one_line(capsys, command[0], "--db = '' is empty")
    nothing_created(tmp_path)


@pytest.mark.parametrize("url", ["sqlite://", "sqlite:///:memory:", "sqlite+pysqlite://",
                                 "sqlite:///file:x?mode=memory&uri=true"])
def test_in_memory_sqlite_is_refused(capsys, tmp_path, url):
    """Before: exit 0 on an empty throwaway store, shown as if it were one."""
    for command in (["status"], ["submit", "--x", "k=4:12:3", "--tau", "2"], ["workers"]):
        assert main([*command, "--db", url]) == 2
        assert "in-memory SQLite" in one_line(capsys, command[0], f"--db = {url!r}")
    nothing_created(tmp_path)


def test_the_application_refuses_them_too(capsys, tmp_path, monkeypatch):
    import slopetui.tui.app
    opened: list[str] = []  # before: the application opened on the default store
    monkeypatch.setattr(slopetui.tui.app, "run_app", lambda url, **_: opened.append(url) or 0)
    assert main(["--db", "", "--no-workers"]) == 2 and not opened
    assert capsys.readouterr().err.startswith("slopetui: error: --db = '' is empty")
    nothing_created(tmp_path)


@pytest.mark.parametrize("log", ["folder", "file/x.log", ""])
def test_worker_log_a_folder_or_no_file(capsys, tmp_path, log):
    """Before: IsADirectoryError from the pool, after the store was created."""
    (tmp_path / "folder").mkdir()
    (tmp_path / "file").write_text("")
    assert main(["worker", "-j", "1", "--exit-when-idle", "--log", log,
                 "--db", f"sqlite:///{tmp_path / 's.db'}"]) == 2
    line = one_line(capsys, "worker", f"--log = {log!r}")
    assert ("is a folder" in line or "is not a folder" in line or "is empty" in line), line
    nothing_created(tmp_path, "folder", "file")


def unwritable_folder(tmp_path: Path) -> Path:
    """A folder this process may not create a file in: a 0500 folder, or for root (who
    writes anywhere, and whom os.access answers yes) sysfs, where even root may not."""
    if os.geteuid() != 0:
        folder = tmp_path / "read-only"
        folder.mkdir(mode=0o500)
        return folder
    return Path("/sys")


def test_worker_log_in_a_folder_it_cannot_write(capsys, tmp_path):
    """Before: PermissionError from the pool's logging, after the store was created."""
    folder = unwritable_folder(tmp_path)
    for log in (folder / "worker.log", folder / "new" / "worker.log"):
        assert main(["worker", "-j", "1", "--exit-when-idle", "--log", str(log),
                     "--db", f"sqlite:///{tmp_path / 's.db'}"]) == 2
        line = one_line(capsys, "worker", f"--log = {str(log)!r} cannot be created in")
        assert "allowed a file in a folder you may write" in line
        assert not log.exists() and not (folder / "new").exists()
    nothing_created(tmp_path, *(["read-only"] if folder.parent == tmp_path else []))


def test_figure_to_an_empty_name(db, db_url, capsys, tmp_path):
    """Before: exit 0, and sweep-1.pdf written in the current folder."""
    sweep = submit_quick(db, 3).sweep_id
    assert main(["figure", str(sweep), "-o", "", "--db", db_url]) == 2
    assert ".pdf, .svg or .png" in one_line(capsys, "figure", "--output = '' is empty")
    assert not list(tmp_path.glob("sweep-*"))


def test_export_to_an_empty_name(db, db_url, capsys):
    """Before: exit 0, and the runs on stdout, as without -o (as figure's -o '')."""
    sweep = submit_quick(db, 3).sweep_id
    for form in ("--csv", "--json"):
        assert main(["export", str(sweep), form, "-o", "", "--db", db_url]) == 2
        assert "allowed a file name" in one_line(capsys, "export", "--output = '' is empty")


def test_continue_to_where_it_starts(capsys, tmp_path):
    """Before: a branch of two points, one step past --to, and exit 0."""
    for extra in ([], ["--submit", "--db", f"sqlite:///{tmp_path / 's.db'}"]):
        assert main(["continue", "--param", "k", "--k", "10", "--tau", "10", "--to", "10",
                     *extra]) == 2
        assert "a value other than the start, k = 10" in one_line(capsys, "continue", "to = ")
    nothing_created(tmp_path)


@pytest.mark.parametrize("args,field", [
    (["continue", "--param", "k", "--points", "x"], "points = 'x'"),
    (["continue", "--param", "k", "--max-step", "0"], "max-step = '0'"),
    (["continue", "--param", "k", "--max-step", "nan"], "max-step = 'nan'"),
    (["continue", "--param", "k", "--from-run", "9" * 30], "from-run = "),
    (["hysteresis", "--param", "k", "--from", "8", "--to", "9", "--points", "1e3"], "points = "),
    (["hysteresis", "--param", "k", "--from", "8", "--to", "9", "--t-settle", "x"], "t-settle = "),
    (["hysteresis", "--param", "k", "--from", "8", "--to", "9", "--window", "inf"], "window = "),
    (["hysteresis", "--show", "9" * 30], "show = "),
    (["branch", "9" * 30], "ID = "),        # found in review: OverflowError from SQLite
    (["branch", "x"], "ID = 'x'"),
    (["nblock", "--seed", "-1"], "--seed = -1"),  # a ValueError traceback from numpy
])
def test_numbers_that_argparse_read_are_one_line_too(capsys, tmp_path, args, field):
    """Before: argparse's usage and error (two lines), or an OverflowError from SQL."""
    assert main(args) == 2
    assert "allowed" in one_line(capsys, args[0], field)
    nothing_created(tmp_path)
