"""`slopetui run` as a user types it."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import pytest

from slopetui.cli import main

KEYS = {"regime", "lambda_max", "lambda_err", "amplitude", "period", "peaks", "drift",
        "t_blowup", "runtime_s"}


def run_cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "slopetui", *args], capture_output=True,
                          text=True, timeout=300)


def test_json_has_the_contract_keys():
    out = run_cli("run", "--k", "4", "--t-end", "2e4", "--method", "rk4", "--json")
    assert out.returncode == 0, out.stderr
    rec = json.loads(out.stdout)
    assert KEYS <= rec.keys()
    assert rec["regime"] == "sliding" and rec["t_blowup"] is None
    assert rec["lambda_max"] < 0 and rec["lambda_err"] > 0


def test_text_output(capsys):
    assert main(["run", "--k", "10", "--t-end", "5e3", "--window", "500", "--method", "rk4"]) == 0
    text = capsys.readouterr().out
    for label in ("regime     oscillatory", "lambda_max", "amplitude", "period", "peaks",
                  "drift", "runtime"):
        assert label in text


def test_blow_up_is_reported(capsys):
    assert main(["run", "--a", "0.035", "--k", "12", "--t-end", "100", "--window", "10",
                 "--json"]) == 0
    captured = capsys.readouterr()
    rec = json.loads(captured.out)
    assert rec["regime"] == "unstable" and 0 < rec["t_blowup"] < 1
    assert "warning" in captured.err and "eq. 12" in captured.err


@pytest.mark.parametrize(
    "args,field",
    [(["--tau", "-1"], "tau"), (["--k", "nan"], "k"), (["--d", "-0.1"], "d"),
     (["--dt", "0"], "dt"), (["--dt", "5", "--tau", "1"], "dt"), (["--t-end", "-3"], "t_end"),
     (["--window", "2e5"], "window"), (["--a", "x"], "a")],
)
def test_bad_input_names_the_field_and_exits_nonzero(args, field, capsys):
    assert main(["run", *args]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert f"{field} = " in captured.err and "allowed" in captured.err


def test_json_has_no_nan_literals(capsys):
    main(["run", "--k", "4", "--t-end", "1e3", "--window", "100", "--no-lyap", "--json"])
    text = capsys.readouterr().out
    assert "NaN" not in text
    rec = json.loads(text)
    assert rec["lambda_max"] is None and not math.isnan(rec["amplitude"])
