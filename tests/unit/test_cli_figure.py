"""`slopetui figure` as a user types it: a sweep's diagram, a run, runs compared, and bad
input refused before anything is computed or written."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import pytest

from slopetui.cli import main
from slopetui.figures import DIAGRAM_SIZE, PNG_DPI
from slopetui.figures.output import FACTS_PREFIX
from slopetui.store.database import Database
from slopetui.sweeps.spec import parse_spec
from slopetui.sweeps.submit import submit
from tests.support import QUICK_SOLVER, finish_all, submit_quick


def plane(db: Database) -> int:
    spec = parse_spec({"x": {"param": "k", "start": 2, "stop": 20, "num": 4},
                       "y": {"param": "tau", "start": 0.5, "stop": 10, "num": 3},
                       "solver": QUICK_SOLVER})
    sweep = submit(db, spec).sweep_id
    finish_all(db)
    return sweep


def data_rows(path: Path) -> list[dict[str, str]]:
    """The rows of a figure's CSV, after the comment line naming what it was computed at."""
    with path.open() as f:
        assert f.readline().startswith(FACTS_PREFIX + "{")
        return list(csv.DictReader(f))


def run_ids(db: Database, sweep: int) -> list[int]:
    from slopetui.store.queries import runs_of
    return [r.id for r in runs_of(db, sweep)]


@pytest.mark.slow  # over 0.5 s: out of the fast loop, still in CI
def test_a_phase_diagram_is_written_with_its_data(db, db_url, tmp_path, capsys):
    import matplotlib.image

    sweep = plane(db)
    out = tmp_path / "plane.png"
    assert main(["figure", str(sweep), "-o", str(out), "--db", db_url]) == 0
    said = capsys.readouterr().out
    assert f"figure written to {out}" in said and "plane.csv" in said and "plane.curves.csv" in said
    image = matplotlib.image.imread(out)
    assert image.shape[:2] == (round(DIAGRAM_SIZE[1] * PNG_DPI), round(DIAGRAM_SIZE[0] * PNG_DPI))
    rows = data_rows(tmp_path / "plane.csv")
    assert len(rows) == 12 and {"k", "tau", "regime"} <= set(rows[0])
    assert "sliding" in {r["regime"] for r in rows} and len({r["regime"] for r in rows}) >= 2
    curve = data_rows(tmp_path / "plane.curves.csv")
    assert curve and {r["curve"] for r in curve} == {"hopf"}
    assert all(2 <= float(r["k"]) <= 20 and 0.5 <= float(r["tau"]) <= 10 for r in curve)


@pytest.mark.slow  # over 0.5 s: out of the fast loop, still in CI
def test_the_default_name_is_the_sweeps_in_the_current_folder(db, db_url, tmp_path, monkeypatch):
    submit_quick(db, 3)
    finish_all(db)
    work = tmp_path / "work"
    work.mkdir()
    monkeypatch.chdir(work)
    assert main(["figure", "1", "--db", db_url]) == 0
    assert sorted(p.name for p in work.iterdir()) == ["sweep-1.csv", "sweep-1.pdf"]
    assert (work / "sweep-1.pdf").read_bytes().startswith(b"%PDF")


@pytest.mark.slow  # over 0.5 s: out of the fast loop, still in CI
def test_runs_are_recomputed_and_compared(db, db_url, tmp_path, capsys):
    sweep = submit_quick(db, 2).sweep_id
    finish_all(db)
    a, b = run_ids(db, sweep)
    out = tmp_path / "cmp.svg"
    assert main(["figure", "--run", str(a), "--run", str(b), "-o", str(out), "--db", db_url]) == 0
    captured = capsys.readouterr()
    assert f"recomputing run {a}" in captured.err and f"recomputing run {b}" in captured.err
    svg = out.read_text()
    assert svg.lstrip().startswith("<?xml") and "<svg" in svg
    rows = data_rows(tmp_path / "cmp.csv")
    assert {int(r["run_id"]) for r in rows} == {a, b}
    assert all(math.isfinite(float(r["y"])) for r in rows[:100])


BAD = [
    (["figure"], "give a SWEEP or one or more --run"),
    (["figure", "1", "--run", "1"], "not both"),
    (["figure", "--run", "1", "--fold"], "--fold and --no-hopf apply to a sweep"),
    (["figure", "--run", "1", "--run", "1"], "the same run twice"),
    (["figure", *[a for i in range(1, 10) for a in ("--run", str(i))]], "allowed 1 to 8 runs"),
    (["figure", "x"], "SWEEP = 'x' is out of range"),
    (["figure", "--run", "0"], "--run = 0 is out of range"),
    (["figure", "1", "-o", "{tmp}/fig.jpg"], "unknown extension '.jpg'"),
    (["figure", "1", "-o", "{tmp}/missing/fig.pdf"], "--output"),
    (["figure", "1", "-o", "{tmp}"], "--output"),
    (["figure", "99"], "no sweep with id 99"),
    (["figure", "--run", "999"], "--run 999: there is no such run"),
    (["figure", "2", "--fold"], "--fold draws over a (k, tau)"),
]


@pytest.mark.parametrize("args,error", BAD)
def test_bad_input_is_refused_and_nothing_is_written(args, error, db, db_url, tmp_path, monkeypatch,
                                                     capsys):
    submit_quick(db, 2)  # sweep 1: runs 1, 2, not computed
    submit_quick(db, 2)  # sweep 2: a 1-D sweep (no fold plane)
    work = tmp_path / "work"
    work.mkdir()
    monkeypatch.chdir(work)
    argv = [a.replace("{tmp}", str(work)) for a in args]
    assert main([*argv, "--db", db_url]) == 2
    err = capsys.readouterr().err
    assert error in err and "Traceback" not in err, err
    assert list(work.iterdir()) == []


def test_a_missing_folder_is_named_with_the_allowed_input(db, db_url, tmp_path, capsys):
    submit_quick(db, 2)
    target = tmp_path / "nowhere" / "fig.pdf"
    assert main(["figure", "1", "-o", str(target), "--db", db_url]) == 2
    err = capsys.readouterr().err
    assert str(target.parent) in err and "--output" in err
    assert not target.parent.exists()


@pytest.mark.slow  # over 0.5 s: out of the fast loop, still in CI
def test_figure_help_is_light():
    """Building the parser (every --help) loads no matplotlib: the figure command imports
    it in its handler."""
    import subprocess
    import sys
    probe = ("import sys; from slopetui.cli import build_parser; build_parser(); "
             "print('matplotlib' in sys.modules, 'pandas' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["False", "False"]


def test_the_output_must_be_checked_before_the_store_is_read(db_url, tmp_path, capsys):
    """A bad output path is refused without opening (or creating) the store."""
    store = Path(db_url.removeprefix("sqlite:///"))
    assert not store.exists()
    assert main(["figure", "1", "-o", str(tmp_path / "fig.gif"), "--db", db_url]) == 2
    assert not store.exists()
