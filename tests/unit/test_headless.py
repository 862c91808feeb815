"""The headless commands as a user types them: submit, status, runs, export, show, sql,
cancel, pause, resume. Bad input gets a clear error and writes nothing."""

from __future__ import annotations

import csv
import io
import json
import sqlite3

import pytest

from slopetui.cli import main
from slopetui.store.open import open_store
from tests.support import finish_all

GOOD_TOML = """
name = "fig 4A, short"
[x]
param = "k"
start = 4
stop = 12
num = 5
[y]
param = "tau"
start = 1
stop = 10
num = 3
spacing = "log"
[fixed]
delta = 0.1
[solver]
method = "rk4"
t_end = 200
window = 100
"""


def cli(capsys, *args):
    code = main(list(args))
    out = capsys.readouterr()
    return code, out.out, out.err


def count_rows(db_path, table="runs"):
    if not db_path.exists():
        return 0
    with sqlite3.connect(db_path) as conn:
        return conn.execute(f"SELECT count(*) FROM {table}").fetchone()[0]


def test_submit_from_toml_and_from_flags(tmp_path, capsys):
    db = tmp_path / "s.db"
    spec = tmp_path / "spec.toml"
    spec.write_text(GOOD_TOML)
    code, out, _ = cli(capsys, "submit", str(spec), "--db", f"sqlite:///{db}", "--json")
    assert code == 0 and json.loads(out) == {"sweep_id": 1, "n_runs": 15, "n_cached": 0}
    code, out, _ = cli(capsys, "submit", "--x", "tau=0.1:60:4:log", "--k", "12", "--a", "0.5",
                       "--t-end", "100", "--window", "50", "--db", f"sqlite:///{db}")
    assert code == 0 and "sweep 2: 4 runs queued" in out
    with sqlite3.connect(db) as conn:
        taus = [r[0] for r in conn.execute("SELECT tau FROM runs WHERE sweep_id = 2 ORDER BY ix")]
        ks = {r[0] for r in conn.execute("SELECT k FROM runs WHERE sweep_id = 2")}
        a = {r[0] for r in conn.execute("SELECT a FROM runs WHERE sweep_id = 2")}
    assert taus == pytest.approx([0.1, 0.1 * 600 ** (1 / 3), 0.1 * 600 ** (2 / 3), 60.0])
    assert ks == {12.0} and a == {0.5}


@pytest.mark.parametrize("args, field", [
    (["--x", "q=1:2:3"], "x.param: unknown parameter 'q'"),
    (["--x", "k=1:2:0"], "x.num"),
    (["--x", "k=3:3:5"], "x.stop: the range is empty"),
    (["--x", "tau=-1:5:3"], "x.tau: tau = -1.0 is out of range: allowed tau >= 0"),
    (["--x", "k=1:2:3", "--tau", "-2"], "fixed.tau"),
    (["--x", "k=abc:2:3"], "x.start: expected a number, got 'abc'"),
    (["--x", "k=1:2:3", "--y", "k=1:2:3"], "y.param: k is already swept on x"),
    (["--x", "k=0:2:3:log"], "x.start: log spacing needs start > 0"),
    (["--x", "k=1:2:3", "--t-end", "10", "--window", "20"], "solver.window"),
    (["--x", "k=1:2"], "--x: expected PARAM=START:STOP:NUM"),
    (["--x", "tau=1:0.05:3", "--dt", "0.1"], "solver.dt: dt = 0.1 is out of range"),
    (["--x", "d=1e-3:-1:4", "--y", "tau=1:2:2"], "x.d"),
    ([], "x: missing"),
])
def test_bad_specs_give_a_clear_error_and_write_nothing(tmp_path, capsys, args, field):
    db = tmp_path / "bad.db"
    code, out, err = cli(capsys, "submit", *args, "--db", f"sqlite:///{db}")
    assert code == 2 and out == ""
    assert field in err and err.startswith("slopetui submit: error:")
    assert not db.exists()  # validated before the database is even opened


@pytest.mark.parametrize("text, field", [
    ("x = [", "not valid TOML"),
    ("[x]\nparam = 'k'\nstart = 1\nstop = 2\nnum = 3\n[fixed]\ntau = 'ten'", "fixed.tau: expected a number"),
    ("[x]\nparam = 'k'\nstart = 1\nstop = 2\nnum = 3\nsteps = 4", "x.steps: unknown key"),
    ("[x]\nparam = 'k'\nstart = 1\nstop = 2\nnum = 3\n[fixed]\nk = 2", "fixed.k: k is swept on x"),
    ("[x]\nparam = 'k'\nstart = 1\nstop = 2\nnum = 3\n[solver]\nmethod = 'rk45'", "solver.method"),
])
def test_bad_toml_specs_write_nothing_to_an_existing_store(tmp_path, capsys, text, field):
    db = tmp_path / "s.db"
    good = tmp_path / "good.toml"
    good.write_text(GOOD_TOML)
    assert cli(capsys, "submit", str(good), "--db", f"sqlite:///{db}")[0] == 0
    bad = tmp_path / "bad.toml"
    bad.write_text(text)
    code, _, err = cli(capsys, "submit", str(bad), "--db", f"sqlite:///{db}")
    assert code == 2 and field in err
    assert count_rows(db) == 15 and count_rows(db, "sweeps") == 1


def test_big_sweeps_ask_for_yes(tmp_path, capsys):
    db = tmp_path / "s.db"
    code, _, err = cli(capsys, "submit", "--x", "k=1:20:100", "--y", "tau=1:10:100",
                       "--db", f"sqlite:///{db}")
    assert code == 2 and "10000 runs" in err and "--yes" in err and not db.exists()


def dump(db_path):
    with sqlite3.connect(db_path) as conn:
        return list(conn.iterdump())


def test_status_runs_export_show_after_a_sweep(tmp_path, capsys):
    url = f"sqlite:///{tmp_path / 's.db'}"
    spec = tmp_path / "spec.toml"
    spec.write_text(GOOD_TOML)
    cli(capsys, "submit", str(spec), "--db", url)
    code, out, _ = cli(capsys, "status", "--db", url)
    assert code == 0 and "0/15" in out and "no live workers" in out
    finish_all(open_store(url))
    code, out, _ = cli(capsys, "status", "--all", "--json", "--db", url)
    sweep = json.loads(out)["sweeps"][0]
    assert sweep["status"] == "done" and sweep["counts"] == {"done": 15}
    code, out, _ = cli(capsys, "runs", "--sweep", "1", "--regime", "sliding", "--db", url)
    assert code == 0 and "sliding" in out and "oscillatory" not in out
    code, out, _ = cli(capsys, "export", "1", "--csv", "--db", url)
    rows = list(csv.DictReader(io.StringIO(out)))
    assert len(rows) == 15 and {r["status"] for r in rows} == {"done"}
    sliding = [r for r in rows if r["regime"] == "sliding"]
    assert sliding and all(r["period"] == "nan" for r in sliding)  # NaN spelled out
    assert all(r["t_blowup"] == "" for r in rows)                  # no blow-up: empty
    code, out, _ = cli(capsys, "show", "1", "--width", "80", "--height", "24", "--color",
                       "never", "--db", url)
    assert code == 0 and len(out.rstrip("\n").split("\n")) == 24
    assert "Hopf (exact)" in out and "sliding (" in out and "(15/15 done)" in out


def test_cancel_pause_resume(tmp_path, capsys):
    url = f"sqlite:///{tmp_path / 's.db'}"
    cli(capsys, "submit", "--x", "k=4:8:3", "--t-end", "100", "--window", "50", "--db", url)
    assert "is paused" in cli(capsys, "pause", "1", "--db", url)[1]
    assert "is active" in cli(capsys, "resume", "1", "--db", url)[1]
    assert cli(capsys, "cancel", "1", "--db", url)[1] == \
        "sweep 1 cancelled: 3 queued runs cancelled\n"
    code, _, err = cli(capsys, "cancel", "7", "--db", url)
    assert code == 2 and "no sweep with id 7" in err


def test_one_dispatch_of_sweep_actions(tmp_path):
    """The CLI and the application's keys both call control.apply, by name."""
    from slopetui.sweeps import control

    db = open_store(f"sqlite:///{tmp_path / 's.db'}")
    try:
        with pytest.raises(control.UnknownSweep):
            control.apply(db, "pause", 1)
        with pytest.raises(ValueError, match="one of pause, resume, cancel"):
            control.apply(db, "dispose", 1)  # no name outside ACTIONS is called
    finally:
        db.dispose()


WRITES = [
    "INSERT INTO sweeps (name, spec, x_param, n_runs, status) VALUES ('x', '[]', 'k', 0, 'active')",
    "UPDATE runs SET regime = 'oscillatory'",
    "DELETE FROM runs",
    "DROP TABLE runs",
    "CREATE TABLE evil (x)",
    "PRAGMA query_only = 0",
    "ATTACH DATABASE '{tmp}/other.db' AS other",
    "VACUUM INTO '{tmp}/copy.db'",
]


@pytest.mark.parametrize("statement", WRITES)
def test_sql_refuses_writes_at_the_database_level(tmp_path, capsys, statement):
    db = tmp_path / "s.db"
    url = f"sqlite:///{db}"
    cli(capsys, "submit", "--x", "k=4:8:3", "--t-end", "100", "--window", "50", "--db", url)
    before = dump(db)
    code, _, err = cli(capsys, "sql", statement.replace('{tmp}', str(tmp_path)), "--db", url)
    assert code == 2 and "refused" in err, err
    assert count_rows(db) == 3 and count_rows(db, "sweeps") == 1
    assert not (tmp_path / "other.db").exists()
    assert dump(db) == before


def test_sql_reads(tmp_path, capsys):
    url = f"sqlite:///{tmp_path / 's.db'}"
    cli(capsys, "submit", "--x", "k=4:8:3", "--t-end", "100", "--window", "50", "--db", url)
    code, out, _ = cli(capsys, "sql", "SELECT k, status FROM runs ORDER BY k", "--db", url)
    assert code == 0 and out.split("\n")[0].split() == ["k", "status"] and "(3 rows)" in out
    code, out, _ = cli(capsys, "sql", "SELECT count(*) AS n FROM runs", "--json", "--db", url)
    assert json.loads(out) == {"n": 3}
    code, _, err = cli(capsys, "sql", "SELEC nonsense", "--db", url)
    assert code == 2 and "syntax error" in err


def test_sql_reads_the_schema_with_pragmas(tmp_path, capsys):
    url = f"sqlite:///{tmp_path / 's.db'}"
    cli(capsys, "submit", "--x", "k=4:8:3", "--t-end", "100", "--window", "50", "--db", url)
    code, out, err = cli(capsys, "sql", "PRAGMA table_info(runs)", "--db", url)
    assert code == 0 and "lambda_max" in out, err
