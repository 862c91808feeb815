"""slopetui.json_text, the one encoder of every JSON output: strict JSON, NaN and ±inf as
null, numpy's values as Python's; and the commands that write JSON through it."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest

from slopetui.cli import main
from slopetui.json_text import json_text
from tests.support import finish_all


def strict(text: str):
    """json.loads that fails on NaN, Infinity and -Infinity (Python writes them by default)."""
    return json.loads(text, parse_constant=lambda name: pytest.fail(f"{name} in JSON"))


def test_non_finite_numbers_are_null_wherever_they_are():
    value = {"a": math.nan, "b": [1.5, math.inf, -math.inf], "c": ({"d": np.float64("nan")},),
             "e": np.array([[1.0, np.nan], [np.inf, 2.0]]), "f": np.float32(-np.inf)}
    assert strict(json_text(value)) == {"a": None, "b": [1.5, None, None], "c": [{"d": None}],
                                        "e": [[1.0, None], [None, 2.0]], "f": None}


def test_numpy_scalars_are_the_python_values_they_hold():
    """Before: "Object of type bool is not JSON serializable" (a numpy.bool_ in run's record)."""
    value = {"settled": np.bool_(True), "n": np.int64(7), "x": np.float64(0.25),
             "u": np.uint8(3), "list": [np.bool_(False)], "empty": np.array([])}
    assert json_text(value) == ('{"settled": true, "n": 7, "x": 0.25, "u": 3, "list": [false], '
                                '"empty": []}')


def test_text_is_escaped_for_a_terminal_unless_asked_for_as_stored():
    name = "\x1b]0;owned\x07 \u202e\x9b"
    assert json_text(name) == '"\\u001b]0;owned\\u0007 \\u202e\\u009b"'
    assert json.loads(json_text(name, ensure_ascii=False)) == name


def test_other_types_go_to_the_default_hook_or_fail():
    from datetime import date
    assert json_text({"d": date(2026, 1, 2)}, default=str) == '{"d": "2026-01-02"}'
    with pytest.raises(TypeError):
        json_text({"d": date(2026, 1, 2)})


def test_the_encoder_does_not_load_numpy():
    """`slopetui status --json` starts without numpy (tests/integration/test_startup.py)."""
    code = "import sys, slopetui.json_text; print('numpy' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_run_json_of_a_continuum_holds_a_numpy_bool(capsys):
    """Before: TypeError "Object of type bool is not JSON serializable", a traceback: the
    classifier's `settled` of a continuum is a numpy.bool_ (core.classify)."""
    # (k = 15.047, tau = 20 at t_end 3e4 was a continuum only through a plateau's ripple
    # maxima, core.returns.distinct_maxima: it returns after 2 maxima, slowly modulated)
    assert main(["run", "--k", "20", "--tau", "30", "--delta", "0.1", "--t-end", "5000",
                 "--no-lyap", "--json"]) == 0
    rec = strict(capsys.readouterr().out)
    assert rec["settled"] in (True, False)
    assert rec["attractor"] in ("chaotic", "torus", "unsettled", "undetermined")  # a continuum
    assert rec["period"] is None and rec["lambda_max"] is None  # NaN: null


def test_a_run_has_the_same_json_values_from_run_and_from_export(db, db_url, capsys):
    """Before: export --json wrote "nan" where run --json wrote null (a sliding run's
    period, lambda_max without Lyapunov exponents)."""
    # one stop rule for both (run's default is t_end, submit's certified)
    solver = ["--method", "rk4", "--dt", "0.01", "--t-end", "200", "--window", "100", "--no-lyap",
              "--stop", "t_end"]
    assert main(["run", "--k", "4", "--tau", "2", *solver, "--json"]) == 0
    alone = strict(capsys.readouterr().out)
    assert alone["regime"] == "sliding" and alone["period"] is None
    assert main(["submit", "--x", "k=4:5:2", "--tau", "2", *solver, "--db", db_url]) == 0
    capsys.readouterr()
    finish_all(db)
    assert main(["export", "1", "--json", "--db", db_url]) == 0
    stored = next(r for r in strict(capsys.readouterr().out) if r["k"] == 4)
    same = [key for key in alone if key in stored and key != "runtime_s"]
    # all but runtime_s (history is a column too) and what the run was computed at, which
    # the export's flat rows hold as columns (slopetui.provenance)
    assert len(same) == len(alone) - 4
    assert {key: stored[key] for key in same} == {key: alone[key] for key in same}
    flat = {**alone["params"], **alone["solver"],
            **{f"engine_{key}": value for key, value in alone["engine"].items()}}
    assert {key: stored[key] for key in flat} == flat
