"""Property-based tests of the command line, with hypothesis:

- random valid points and options for every ``--json`` command that computes (run, orbit,
  continue, hysteresis) give strict JSON: parseable with NaN, Infinity and -Infinity
  refused (slopetui.json_text writes null for them), exit status 0;
- random invalid values of their options (out of range, NaN, ±inf, huge, empty, garbage)
  give one line on stderr naming the option, exit status 2, and nothing written: no
  store, no default store, nothing in the current folder.

Each example is short (t_end of a few hundred, 3 branch points), so that the file stays
under ~20 s; the CLI runs in this process (slopetui.cli.main), as tests/unit/test_cli.py.
Options with ``choices`` (--method, --param) are argparse's, which prints its usage too.
"""

from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from core.result_fields import JSON_KEYS
from slopetui.cli import main


def quick(examples: int) -> settings:
    """``examples`` examples without a deadline (the first may compile a kernel), and no
    example database (it would write .hypothesis/ into the checkout). The fixtures are set
    once per test (capsys is read after each example; the bad-input test writes into a
    folder of its own per example)."""
    return settings(max_examples=examples, deadline=None, database=None,
                    suppress_health_check=[HealthCheck.function_scoped_fixture])


@pytest.fixture(autouse=True)
def private_home(tmp_path, monkeypatch):
    """The default store's and the pools' folders in the test's folder, no $SLOPETUI_DB."""
    monkeypatch.setenv("XDG_DATA_HOME", str(tmp_path / "data"))
    monkeypatch.setenv("XDG_STATE_HOME", str(tmp_path / "state"))
    monkeypatch.delenv("SLOPETUI_DB", raising=False)


def strict_json(text: str) -> object:
    def refuse(name: str) -> None:
        raise AssertionError(f"{name} in the JSON output")
    return json.loads(text, parse_constant=refuse)


def number(low: float, high: float) -> st.SearchStrategy[str]:
    """A number in [low, high] as a user types it."""
    return st.floats(low, high, allow_nan=False).map(lambda x: f"{x:.6g}")


# -- valid input: strict JSON --------------------------------------------------------------

@quick(12)
@given(k=number(0, 25), tau=number(0.5, 20), d=number(0, 1e-3), delta=number(-0.5, 0.5),
       a=number(2.9, 3.5), method=st.sampled_from(["euler", "rk4", "stiff"]),
       t_end=number(50, 300), lyap=st.booleans(), history=st.sampled_from(["constant", "consistent"]))
def test_run_json_is_strict(capsys, k, tau, d, delta, a, method, t_end, lyap, history):
    argv = ["run", "--k", k, "--tau", tau, "--d", d, "--delta", delta, "--a", a,
            "--method", method, "--t-end", t_end, "--history", history, "--json"]
    assert main(argv + ([] if lyap else ["--no-lyap"])) == 0
    rec = strict_json(capsys.readouterr().out)
    assert isinstance(rec, dict) and list(rec) == [*JSON_KEYS, "history", "params", "solver",
                                                   "engine"]
    assert rec["settled"] in (True, False) and isinstance(rec["peaks"], list)


@quick(3)
@given(k=number(9, 14), tau=number(8, 12), t_seed=number(300, 800))
def test_orbit_json_is_strict(capsys, k, tau, t_seed):
    status = main(["orbit", "--k", k, "--tau", tau, "--dt", "0.05", "--t-seed", t_seed, "--json"])
    captured = capsys.readouterr()
    if status == 1:  # no orbit there: said in one line, nothing on stdout
        assert captured.out == "" and len(captured.err.splitlines()) == 1
        return
    assert status == 0
    rec = strict_json(captured.out)
    assert isinstance(rec, dict) and rec["period"] > 0 and rec["stable"] in (True, False)


@quick(2)
@given(param=st.sampled_from(["k", "tau", "a"]), points=st.integers(2, 3),
       max_step=number(0.01, 0.5))
def test_continue_json_is_strict(capsys, param, points, max_step):
    status = main(["continue", "--param", param, "--k", "12", "--tau", "9", "--dt", "0.05",
                   "--points", str(points), "--max-step", max_step, "--json"])
    assert status == 0, capsys.readouterr().err
    rec = strict_json(capsys.readouterr().out)
    assert isinstance(rec, dict) and 1 <= len(rec["branch"]) <= points


@quick(3)
@given(start=number(4, 14), width=number(0.5, 4), points=st.integers(2, 3),
       t_settle=number(60, 200), d=st.sampled_from(["0", "1e-4"]))
def test_hysteresis_json_is_strict(capsys, start, width, points, t_settle, d):
    stop = f"{float(start) + float(width):.6g}"
    status = main(["hysteresis", "--param", "k", "--from", start, "--to", stop, "--points",
                   str(points), "--tau", "2", "--d", d, "--t-settle", t_settle, "--window", "40",
                   "--json"])
    assert status == 0, capsys.readouterr().err
    rec = strict_json(capsys.readouterr().out)
    assert isinstance(rec, dict) and 1 <= len(rec["up"]) <= points


# -- invalid input: one line naming the option, exit 2, nothing written --------------------

#: Values no numeric option takes.
GARBAGE = st.sampled_from(["nan", "NaN", "inf", "-inf", "Infinity", "", " ", "x", "1e400",
                           "-1e400", "0x10", "True", "1,5", "1.5.2", "\x1b[2J", "٣.٥e"])


def huge(sign: int = 1) -> st.SearchStrategy[str]:
    return st.floats(1e12, 1e300).map(lambda x: f"{sign * x:.6g}")


def negative() -> st.SearchStrategy[str]:
    return st.floats(-1e6, -1e-6).map(lambda x: f"{x:.6g}")


#: (command and its valid options, the option drawn bad, its name in the message, bad values
#: beside GARBAGE). Every other option is valid and quick, should the bad one be accepted.
RUN = ["run", "--t-end", "100"]
ORBIT = ["orbit", "--k", "10", "--tau", "10", "--t-seed", "300"]
CONTINUE = ["continue", "--param", "k", "--k", "10", "--tau", "10", "--points", "2"]
HYSTERESIS = ["hysteresis", "--param", "k", "--from", "8", "--to", "9", "--points", "2",
              "--tau", "2", "--t-settle", "100", "--window", "50"]
CASES = [
    (RUN, "--k", "k", negative()), (RUN, "--tau", "tau", negative()),
    (RUN, "--d", "d", negative()), (RUN, "--a", "a", st.nothing()),
    (RUN, "--v", "v", st.nothing()), (RUN, "--delta", "delta", st.nothing()),
    (RUN, "--dt", "dt", st.one_of(negative(), st.just("0"), huge())),
    (RUN, "--t-end", "t_end", st.one_of(negative(), st.just("0"), huge())),
    (RUN, "--window", "window", st.one_of(negative(), number(101, 1e6))),
    (RUN, "--history", "history", st.sampled_from(["run:0", "run:" + "9" * 30, "run:-1", "run:", "last"])),
    (ORBIT, "--t-seed", "t-seed", st.one_of(negative(), number(0, 99), huge())),
    (ORBIT, "--dt", "dt", st.one_of(negative(), st.just("0"), number(10.5, 1e6))),
    (ORBIT, "--tau", "tau", st.one_of(negative(), st.just("0"))),
    (CONTINUE, "--to", "to", st.just("10")),  # where it starts
    (CONTINUE, "--points", "points", st.integers(-10**30, 1).map(str)),
    (CONTINUE, "--max-step", "max-step", st.one_of(negative(), st.just("0"), huge())),
    (CONTINUE, "--from-run", "from-run", st.sampled_from(["0", "-3", "9" * 30])),
    (HYSTERESIS, "--points", "points", st.one_of(st.integers(-10**30, 1), st.integers(2001, 10**30)).map(str)),
    (HYSTERESIS, "--t-settle", "t-settle", st.one_of(negative(), number(0, 19), huge())),
    (HYSTERESIS, "--window", "window", st.one_of(negative(), number(0, 0.099), number(101, 1e9))),
    (HYSTERESIS, "--to", "to", st.just("8")),  # where it starts
    (HYSTERESIS, "--show", "show", st.sampled_from(["0", "-1", "9" * 30, "x"])),
]


def bad_input() -> st.SearchStrategy[tuple[list[str], str]]:
    """(argv, the option's name in the message)."""
    def one(case: tuple[list[str], str, str, st.SearchStrategy[str]]) -> st.SearchStrategy[tuple[list[str], str]]:
        base, flag, field, bad = case
        argv = list(base)
        if flag in base:  # given once: the bad value
            i = base.index(flag)
            argv = base[:i] + base[i + 2:]
        if base[0] != "orbit":  # the store they may open (orbit has none)
            argv += ["--db", "sqlite:///s.db"]
        return st.one_of(GARBAGE, bad).map(lambda value: ([*argv, f"{flag}={value}"], field))
    return st.one_of([one(case) for case in CASES])


@quick(100)
@given(case=bad_input(), as_json=st.booleans())
def test_bad_input_is_one_line_naming_the_option(capsys, tmp_path, case, as_json):
    argv, field = case
    with tempfile.TemporaryDirectory(dir=tmp_path) as folder:
        here = os.getcwd()
        os.chdir(folder)
        try:
            status = main([*argv, *(["--json"] if as_json else [])])
        finally:
            os.chdir(here)
        assert list(Path(folder).iterdir()) == []  # no store, no file
    captured = capsys.readouterr()
    lines = captured.err.splitlines()
    assert status == 2 and captured.out == "", (argv, captured)
    assert len(lines) == 1 and f"{field} = " in lines[0], (argv, captured.err)
    assert "allowed" in lines[0] and "Traceback" not in captured.err
    assert not (tmp_path / "data").exists()  # no default store either


def test_the_cases_cover_every_computing_command():
    assert {base[0] for base, *_ in CASES} == {"run", "orbit", "continue", "hysteresis"}
