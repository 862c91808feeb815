"""The command line of the period-doubling curve and of branch switching: what they say when
the branch has no period doubling. The curve itself and the switched branch are checked on
the real period doubling (b = 22.32519 at tau = 2, k = 12) in test_real_crossings.py, on the
branch it walks once for all its tests."""

from __future__ import annotations

import json

import pytest

from slopetui.cli import main

pytestmark = pytest.mark.computation  # only computes: beside the slow tiers (tests/xdist_plan.py)


def test_from_pd_on_a_branch_with_no_period_doubling_says_so(capsys):
    assert main(["continue", "--param", "k", "--param2", "tau", "--from-pd", "--tau", "10",
                 "--to", "5", "--to2", "9"]) == 1
    err = capsys.readouterr().err
    assert "no period doubling on the branch in k up to 5" in err and err.count("\n") == 1


def test_switch_pd_on_a_branch_with_no_period_doubling_says_so(capsys):
    assert main(["continue", "--param", "k", "--from-hopf", "--tau", "10", "--to", "5",
                 "--switch-pd", "--json"]) == 0
    rec = json.loads(capsys.readouterr().out)
    assert [b["type"] for b in rec["bifurcations"]] == []
    assert rec["doubled"] == {"note": "no period doubling on this branch to switch at",
                              "branch": [], "bifurcations": [], "end": ""}
