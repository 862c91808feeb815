"""`slopetui submit SPEC.toml` with bad specs: one line naming the field and what is
allowed, exit status 2, no traceback, and nothing written (not even the store file)."""

from __future__ import annotations

from pathlib import Path

import pytest

from slopetui.cli import main
from slopetui.sweeps.spec import SpecError, parse_spec

AXIS = '[x]\nparam = "k"\nstart = 1\nstop = 2\nnum = 2\n'
HUGE_INT = "1" + "0" * 400  # a TOML integer no float holds


def submit_file(tmp_path: Path, text: str | bytes, *extra: str) -> tuple[int, Path]:
    spec = tmp_path / "spec.toml"
    if isinstance(text, bytes):
        spec.write_bytes(text)
    else:
        spec.write_text(text, encoding="utf-8")
    store = tmp_path / "store.db"
    return main(["submit", str(spec), "--db", f"sqlite:///{store}", *extra]), store


def refused(capsys, store: Path, field: str) -> str:
    captured = capsys.readouterr()
    lines = captured.err.splitlines()
    assert captured.out == "" and len(lines) == 1, captured.err
    assert "Traceback" not in captured.err
    assert lines[0].startswith(f"slopetui submit: error: {field}: "), lines[0]
    assert not store.exists()  # checked before the store is opened: nothing written
    return lines[0]


@pytest.mark.parametrize(
    "text,field,says",
    [  # before: TypeError tracebacks from merging the flags into a table that is not one
        ("solver = [1]\n" + AXIS, "solver", "expected a table"),
        ("fixed = 3\n" + AXIS, "fixed", "expected a table"),
        ("solver = false\n" + AXIS, "solver", "expected a table"),
        # before: name = 0 silently became the default name
        ("name = 0\n" + AXIS, "name", "expected a string"),
        ("name = false\n" + AXIS, "name", "expected a string"),
        # before: OverflowError from float() of an integer beyond any float
        (AXIS.replace("start = 1", f"start = {HUGE_INT}"), "x.start", "finite"),
        (AXIS + f"[fixed]\ntau = {HUGE_INT}\n", "fixed.tau", "finite"),
        # before: "a = nan is out of range" (np.linspace stepped by infinity), no field
        ('[x]\nparam = "a"\nstart = -1e308\nstop = 1e308\nnum = 3\n', "x.stop",
         "wider than the largest float"),
        # siblings that were already refused: keep them so
        ('x = "k"\n', "x", "expected a table"),
        ("name = 5\n" + AXIS, "name", "expected a string"),
        (f"name = \"{'n' * 201}\"\n" + AXIS, "name", "at most 200"),
        (AXIS + "[solver]\nmethod = 1\n", "solver.method", "one of euler, rk4"),
        (AXIS + '[solver]\nlyap = "yes"\n', "solver.lyap", "true or false"),
        (AXIS + "[solver]\ndt = true\n", "solver.dt", "expected a number"),
        (AXIS + "[solver]\ndt = 0\n", "solver.dt", "dt > 0"),
        (AXIS + "[solver]\nt_end = -1\n", "solver.t_end", "t_end > 0"),
        (AXIS + "[solver]\nt_end = inf\n", "solver.t_end", "finite"),
        (AXIS + "[solver]\nwindow = nan\n", "solver.window", "finite"),
        (AXIS + "[solver]\nt_end = 1000\nwindow = 2000\n", "solver.window", "t_end = 1000"),
        (AXIS + "[solver]\nspeed = 1\n", "solver.speed", "unknown key"),
        (AXIS + "[fixed]\nb = true\n", "fixed.b", "expected a number"),
        (AXIS + "[fixed]\nd = -1e-4\n", "fixed.d", "d >= 0"),
        (AXIS + '[fixed]\ntau = "ten"\n', "fixed.tau", "expected a number"),
        (AXIS.replace("num = 2", "num = 2.5"), "x.num", "integer >= 1"),
        (AXIS.replace("num = 2", "num = true"), "x.num", "expected a number"),
        (AXIS.replace("num = 2", "num = 0"), "x.num", "integer >= 1"),
        (AXIS.replace("num = 2", "num = 1e300"), "x.num", "at most"),
        (AXIS.replace("start = 1", "start = nan"), "x.start", "finite"),
        (AXIS.replace("stop = 2", "stop = inf"), "x.stop", "finite"),
        (AXIS.replace("start = 1", "start = 1e999"), "x.start", "finite"),
        (AXIS.replace('"k"', '["k"]'), "x.param", "unknown parameter"),
        (AXIS.replace("num = 2", 'num = 2\nspacing = "cubic"'), "x.spacing", "linear, log"),
        ('[x]\nparam = "tau"\nstart = -1\nstop = 2\nnum = 2\n', "x.tau", "tau >= 0"),
        ('[x]\nparam = "k"\nstart = 0\nstop = 2\nnum = 2\nspacing = "log"\n', "x.start",
         "start > 0"),
        (AXIS + '[y]\nparam = "tau"\nstart = 1\nstop = 2\nnum = 2\n[adaptive]\nlevels = 0\n',
         "adaptive.levels", "from 1 to 8"),
        (AXIS + '[y]\nparam = "tau"\nstart = 1\nstop = 2\nnum = 2\n[adaptive]\nlevels = 2.5\n',
         "adaptive.levels", "from 1 to 8"),
        (AXIS + "[adaptive]\nlevels = 2\n", "adaptive", "needs a phase diagram"),
        ("[solver]\ndt = 0.01\n", "x", "missing"),
    ],
)
def test_a_bad_spec_is_one_line_naming_the_field(tmp_path, capsys, text, field, says):
    code, store = submit_file(tmp_path, text)
    assert code == 2
    assert says in refused(capsys, store, field)


@pytest.mark.parametrize(
    "text,extra,field,says",
    [  # before: accepted, and every run failed 3 times at its worker on 21.8 or 364 TiB
        (AXIS, ["--dt", "1e-12"], "solver.dt", "dt >= 1e-05"),
        (AXIS, ["--tau", "1e9"], "fixed.tau", "tau <= 1.342e+05"),
        ('[x]\nparam = "tau"\nstart = 1\nstop = 1e9\nnum = 3\n', [], "x.stop", "delay history"),
        ('[x]\nparam = "tau"\nstart = 1e9\nstop = 1\nnum = 3\n', [], "x.start", "delay history"),
        (AXIS, ["--t-end", "1e300"], "solver.t_end", "at most 1e10 steps per run"),
        (AXIS, ["--tau", "0", "--dt", "1", "--t-end", "1e9"], "solver.t_end", "lambda_max"),
        # a window too short to classify (60 samples)
        (AXIS, ["--t-end", "10", "--window", "0.1"], "solver.window", "60 samples"),
    ],
)
def test_a_sweep_beyond_the_engines_limits_is_refused(tmp_path, capsys, text, extra, field, says):
    code, store = submit_file(tmp_path, text, *extra)
    assert code == 2
    assert says in refused(capsys, store, field)


def test_a_binary_file_or_a_directory_is_not_a_spec(tmp_path, capsys):
    """Before: a UnicodeDecodeError traceback for the binary file."""
    code, store = submit_file(tmp_path, bytes(range(256)) * 4)
    assert code == 2
    assert "not a text file" in refused(capsys, store, str(tmp_path / "spec.toml"))
    folder = tmp_path / "specs"
    folder.mkdir()
    assert main(["submit", str(folder), "--db", f"sqlite:///{store}"]) == 2
    assert "is a directory" in refused(capsys, store, str(folder))


def test_the_short_default_window_is_stored_explicitly(tmp_path):
    spec = parse_spec({"x": {"param": "k", "start": 1, "stop": 2, "num": 2},
                       "solver": {"t_end": 100}}, submitting=True)
    assert spec.to_dict()["solver"]["window"] == 50.0
    assert parse_spec(spec.to_dict()).solver == spec.solver


def test_a_stored_spec_is_read_back_despite_the_admission_checks():
    """A sweep stored before a limit existed must still load (show, the application and
    the adaptive refinement parse stored specs); only a new sweep is refused."""
    stored = {"name": "old \x1b[31m sweep",
              "x": {"param": "tau", "start": 1, "stop": 1e9, "num": 3},
              "solver": {"method": "euler", "dt": 1e-3, "t_end": 10.0, "window": 0.01}}
    assert parse_spec(stored).name == "old \x1b[31m sweep"
    with pytest.raises(SpecError) as exc:
        parse_spec(stored, submitting=True)
    assert exc.value.field == "name"
    with pytest.raises(SpecError) as exc:
        parse_spec({**stored, "name": "old"}, submitting=True)
    assert exc.value.field == "solver.window"                   # too short to classify
    with pytest.raises(SpecError) as exc:
        parse_spec({**stored, "name": "old", "solver": {"t_end": 10.0}}, submitting=True)
    assert exc.value.field == "x.stop"                          # tau = 1e9: 14.6 TiB
