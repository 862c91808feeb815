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


def test_orbit_json_checks_the_orbit_at_half_the_step(capsys):
    assert main(["orbit", "--k", "10", "--tau", "10", "--json"]) == 0
    check = json.loads(capsys.readouterr().out)["step_check"]
    assert check["dt"] == 0.005 and check["resolved"] is True and check["reason"] == ""
    assert abs(check["period_change"]) < 1e-7 and abs(check["amplitude_change"]) < 1e-6
    assert check["maxima_per_period"] == 1


def test_an_orbit_its_step_does_not_resolve_says_so(capsys):
    """Sharp slips (b = 24, k = 12, tau = 7.43): at dt 0.01 the orbit has amplitude 10.20
    and 13 maxima a period, at 0.005 (and 0.0025, 1e-3) 9.771 and one; the command printed
    the first as the orbit, with nothing to say it is the step's."""
    assert main(["orbit", "--b", "24", "--k", "12", "--tau", "7.43", "--json"]) == 0
    rec = json.loads(capsys.readouterr().out)
    check = rec["step_check"]
    assert rec["maxima_per_period"] > 1 and check["maxima_per_period"] == 1
    assert check["resolved"] is False and check["amplitude_change"] > 0.01
    assert abs(check["amplitude"] - 9.771) < 1e-3
    assert "not resolved at dt 0.01" in check["reason"]
    assert main(["orbit", "--b", "24", "--k", "12", "--tau", "7.43", "--dt", "0.0025"]) == 0
    out = capsys.readouterr().out
    assert "amplitude 9.77108" in out and "1 maximum per period: resolved" in out


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
