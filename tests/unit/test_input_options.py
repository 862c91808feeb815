"""The numeric options and the output files of runs, show, status and export: a bad value
is one line naming the option and its range (argparse's own errors print the usage too),
exit status 2, no traceback."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from slopetui.cli import main
from tests.support import submit_quick


def refused(capsys, command: str, field: str) -> str:
    captured = capsys.readouterr()
    lines = captured.err.splitlines()
    assert captured.out == "" and len(lines) == 1, captured.err
    assert "Traceback" not in captured.err and "usage:" not in captured.err
    assert lines[0].startswith(f"slopetui {command}: error: {field}"), lines[0]
    return lines[0]


@pytest.mark.parametrize(
    "args,field,says",
    [
        (["runs", "--limit", "x"], "--limit", "an integer from 0"),
        (["runs", "--limit", "1e3"], "--limit", "an integer from 0"),
        (["runs", "--limit", "-1"], "--limit", "an integer from 0"),
        (["runs", "--limit", "9" * 30], "--limit", "9223372036854775807"),  # SQL's OverflowError
        (["runs", "--sweep", "0"], "--sweep", "an integer from 1"),
        (["runs", "--sweep", "k"], "--sweep", "an integer from 1"),
        (["show", "0"], "SWEEP", "an integer from 1"),
        (["show", "9" * 30], "SWEEP", "9223372036854775807"),
        (["show", "1", "--width", "5"], "--width", "from 30 to 1000"),
        (["show", "1", "--width", "100000"], "--width", "from 30 to 1000"),   # a huge canvas
        (["show", "1", "--width", "wide"], "--width", "from 30 to 1000"),
        (["show", "1", "--height", "3"], "--height", "from 12 to 1000"),
        (["show", "1", "--height", "1e9"], "--height", "from 12 to 1000"),
        (["status", "0"], "SWEEP", "an integer from 1"),   # before: "no sweeps yet"
        (["status", "x"], "SWEEP", "an integer from 1"),
        (["status", "1", "99"], "SWEEP: no sweep with id 99", ""),
        (["export", "0", "--csv"], "SWEEP", "an integer from 1"),
        (["export", "x", "--csv"], "SWEEP", "an integer from 1"),
        (["export", "99", "--csv"], "SWEEP: no sweep with id 99", ""),
        (["export", "1", "--csv", "-o", "/nonexistent/x.csv"], "--output",
         "No such file or directory"),
    ],
)
def test_a_bad_number_is_one_line_naming_the_option(db, db_url, capsys, args, field, says):
    submit_quick(db, 3)
    assert main([*args, "--db", db_url]) == 2
    assert says in refused(capsys, args[0], field)


def test_export_names_a_target_it_cannot_write(db, db_url, capsys, tmp_path):
    """Before: FileNotFoundError, IsADirectoryError, PermissionError tracebacks."""
    submit_quick(db, 3)
    not_a_folder = tmp_path / "file"
    not_a_folder.write_text("x")
    targets = [tmp_path / "missing" / "x.csv", not_a_folder / "x.csv", tmp_path]
    if os.geteuid() != 0:  # root writes anywhere: a read-only folder refuses only users
        read_only = tmp_path / "read-only"
        read_only.mkdir(mode=0o500)
        targets.append(read_only / "x.csv")
    elif Path("/proc/version").exists():  # read-only even for root
        targets.append(Path("/proc/version"))
    for target in targets:
        assert main(["export", "1", "--csv", "-o", str(target), "--db", db_url]) == 2
        assert str(target) in refused(capsys, "export", "--output: cannot write")
    assert not (tmp_path / "missing").exists()


def test_status_of_given_sweeps_and_show_within_the_limits(db, db_url, capsys):
    sweep = submit_quick(db, 3).sweep_id
    assert main(["status", str(sweep), "--db", db_url]) == 0
    assert "k 4..12" in capsys.readouterr().out
    assert main(["show", str(sweep), "--width", "30", "--height", "12", "--color", "never",
                 "--db", db_url]) == 0
    assert main(["runs", "--limit", "0", "--sweep", str(sweep), "--db", db_url]) == 0
    assert len(capsys.readouterr().out.splitlines()) > 3
