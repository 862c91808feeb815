"""Stored text that would drive a terminal (ESC, OSC, CSI, BEL, C1, bidi overrides), written
straight into a store as another host or tool could, goes through every command and screen
that prints it escaped (slopetui.display_text), and through a file or a pipe byte-exact.
The rule's first half and the names refused at submission: test_input_names.py."""

from __future__ import annotations

import csv
import io
import json
import sys

import pytest
from sqlalchemy import update

from slopetui.cli import main
from slopetui.display_text import terminal_safe
from slopetui.sql_results import QueryDone, run_query
from slopetui.store.database import Database
from slopetui.store.models import Continuation, HysteresisSweep, Run, Sweep, Worker
from slopetui.sweeps.recompute import StoredRun
from slopetui.tui.screens.run_detail import summary_text
from slopetui.tui.screens.sql import format_cell

#: One of each: OSC (sets the window title, ended by BEL), CSI (clears the screen), SGR,
#: a C1 CSI (\x9b: a CSI on its own to some terminals), a bidi override.
HOSTILE = "\x1b]0;owned\x07\x1b[2J\x1b[31mred\x9b1mbold\u202eabc"
SHOWN = terminal_safe(HOSTILE)
#: The raw characters none of which may reach a terminal.
RAW = ("\x1b", "\x07", "\x9b", "\u202e")


def assert_escaped(text: str) -> None:
    assert SHOWN in text, text
    for ch in RAW:
        assert ch not in text, (repr(ch), text)


class Terminal(io.StringIO):
    """stdout as a terminal."""

    def isatty(self) -> bool:
        return True


@pytest.fixture
def hostile(db: Database, evil_sweep: int) -> int:
    """The evil sweep renamed to HOSTILE, its first run failed with a HOSTILE error, and a
    live worker of another host whose id and host name are HOSTILE."""
    with db.transaction() as s:
        s.execute(update(Sweep).where(Sweep.id == evil_sweep).values(name=HOSTILE))
        run = s.get(Run, 1)
        assert run is not None
        run.status, run.error, run.worker_id = "failed", f"Traceback...\n{HOSTILE}", HOSTILE
        s.add(Worker(id=HOSTILE, host=HOSTILE, pid=4242, run_id=None, jobs_done=3))
    return evil_sweep


def test_sql_table_escapes_cells_columns_and_errors(db_url, hostile, capsys):
    assert main(["sql", f"SELECT s.name, r.error AS \"{HOSTILE}\" FROM sweeps s JOIN runs r "
                        "ON r.sweep_id = s.id WHERE r.id = 1", "--db", db_url]) == 0
    out = capsys.readouterr().out
    assert_escaped(out)
    assert out.count(SHOWN) == 3  # the column's name, the sweep's name, the error
    # an error message that quotes text (here the query's; a database may quote data)
    assert main(["sql", f'SELECT * FROM "{HOSTILE}"', "--db", db_url]) == 2
    captured = capsys.readouterr()
    assert_escaped(captured.err)
    assert len(captured.err.splitlines()) == 1


def test_sql_csv_is_byte_exact_into_a_pipe_and_escaped_on_a_terminal(db_url, hostile, capsys,
                                                                     monkeypatch):
    query = ["sql", "SELECT id, name FROM sweeps", "--csv", "--db", db_url]
    assert main(query) == 0
    piped = capsys.readouterr().out  # capsys is not a terminal: a pipe, a file
    expected = io.StringIO()
    csv.writer(expected, lineterminator="\n").writerows([["id", "name"], [hostile, HOSTILE]])
    assert piped == expected.getvalue()
    terminal = Terminal()
    monkeypatch.setattr(sys, "stdout", terminal)
    assert main(query) == 0
    assert terminal.getvalue() == f"id,name\n{hostile},{SHOWN}\n"


def test_sql_json_keeps_the_value_and_no_raw_control(db_url, hostile, capsys):
    assert main(["sql", "SELECT name FROM sweeps", "--json", "--db", db_url]) == 0
    out = capsys.readouterr().out
    assert not any(ch in out for ch in RAW)
    assert json.loads(out) == {"name": HOSTILE}


def test_workers_escapes_ids_and_host_names(db_url, hostile, capsys):
    assert main(["workers", "--db", db_url]) == 0
    out = capsys.readouterr().out
    assert_escaped(out)
    assert out.count(SHOWN) == 2  # "workers on HOST", then the worker's line
    assert main(["workers", "--json", "--db", db_url]) == 0
    out = capsys.readouterr().out
    assert not any(ch in out for ch in RAW)
    assert json.loads(out)["pools"][0]["host"] == HOSTILE


def test_status_runs_and_export_escape(db_url, hostile, capsys):
    for args in (["status"], ["runs"], ["pause", str(hostile)]):
        assert main([*args, "--db", db_url]) == 0
        out = capsys.readouterr().out
        assert not any(ch in out for ch in RAW), (args, out)
    assert main(["status", "--db", db_url]) == 0
    assert_escaped(capsys.readouterr().out)


def test_branch_and_hysteresis_escape_a_stored_error(db, db_url, capsys):
    assert main(["continue", "--param", "k", "--from-hopf", "--tau", "2", "--points", "6",
                 "--submit", "--db", db_url]) == 0
    assert main(["hysteresis", "--param", "k", "--from", "8", "--to", "12", "--points", "4",
                 "--tau", "2", "--t-settle", "300", "--window", "100", "--submit",
                 "--db", db_url]) == 0
    capsys.readouterr()
    with db.transaction() as s:
        for job in (Continuation, HysteresisSweep):
            s.execute(update(job).values(status="failed", error=f"Traceback\n{HOSTILE}"))
    for args in (["branch", "1"], ["hysteresis", "--show", "1"]):
        assert main([*args, "--db", db_url]) == 0
        assert_escaped(capsys.readouterr().out)


def test_the_consoles_cells_and_the_run_detail_are_escaped(db, hostile):
    """What the application's SQL console puts in its grid (a Text: never markup) and the
    run detail's header."""
    engine = db.read_only_engine()
    try:
        done = run_query(engine, "SELECT name, error FROM sweeps, runs WHERE runs.id = 1", 10)
    finally:
        engine.dispose()
    assert isinstance(done, QueryDone)
    cells = [format_cell(v).plain for v in done.rows[0]]
    assert all(not any(ch in c for ch in RAW) for c in cells)
    assert cells[0] == SHOWN and cells[1].endswith(SHOWN)
    assert format_cell("[red]x").plain == "[red]x"
    with db.sessions() as s:
        run = s.get(Run, 1)
        assert run is not None
        header = summary_text(StoredRun.of(run))
    assert_escaped(header)
    assert header.count("\n") == 4  # its five lines kept
