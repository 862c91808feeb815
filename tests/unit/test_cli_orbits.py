"""`slopetui orbit` and `slopetui continue` as a user types them."""

from __future__ import annotations

import json

import pytest

from slopetui.cli import main


def test_orbit_json_has_the_documented_keys(capsys):
    assert main(["orbit", "--k", "10", "--tau", "10", "--json"]) == 0
    rec = json.loads(capsys.readouterr().out)
    assert 10.51 < rec["period"] < 10.52 and rec["stable"] is True
    assert len(rec["multipliers"]) == 10 and all(len(m) == 2 for m in rec["multipliers"])
    assert rec["translation_multiplier"] == 1.0
    assert abs(rec["flow_multiplier"][0] - 1) < 1e-7 and rec["maxima_per_period"] == 1


def test_orbit_text_marks_the_flow_multiplier(capsys):
    assert main(["orbit", "--k", "10", "--tau", "10"]) == 0
    out = capsys.readouterr().out
    assert "stable (0 multipliers outside" in out and "* +1.0000000" in out


def test_no_orbit_is_an_error_that_says_why(capsys):
    assert main(["orbit", "--k", "4", "--tau", "10", "--t-seed", "1000"]) == 1
    captured = capsys.readouterr()
    assert captured.out == "" and "rest" in captured.err


@pytest.mark.parametrize("args,field", [
    (["orbit", "--dt", "0"], "dt"), (["orbit", "--tau", "-1"], "tau"), (["orbit", "--tau", "0"], "tau"),
    (["continue", "--param", "d", "--to", "-1"], "d"), (["continue", "--param", "k", "--to", "x"], "to"),
    (["continue", "--param", "k", "--points", "1"], "points")])
def test_bad_input_names_the_field(args, field, capsys):
    assert main(args) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and f"{field} = " in captured.err and "allowed" in captured.err


def test_delta_is_not_a_branch_parameter(capsys):
    with pytest.raises(SystemExit):
        main(["continue", "--param", "delta"])
    assert "invalid choice" in capsys.readouterr().err


@pytest.mark.slow
def test_continue_from_hopf_gives_criticality_and_the_fold(capsys):
    assert main(["continue", "--param", "k", "--from-hopf", "--tau", "10", "--to", "8",
                 "--json"]) == 0
    rec = json.loads(capsys.readouterr().out)
    assert rec["criticality"] == "subcritical"
    assert abs(rec["hopf"]["value"] - 6.14619) < 1e-4
    folds = [b for b in rec["bifurcations"] if b["type"] == "fold"]
    assert len(folds) == 1 and abs(folds[0]["value"] - 1.2139) < 1e-3
    assert rec["branch"][-1]["value"] > 8 and rec["branch"][-1]["stable"] is True
