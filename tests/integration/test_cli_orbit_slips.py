"""``slopetui orbit`` with --slips and --from-run (the equally spaced n-slip orbits)."""

from __future__ import annotations

import json

from slopetui.cli import main
from slopetui.sweeps.spec import parse_spec
from slopetui.sweeps.submit import submit
from tests.support import finish_all


def test_the_three_slip_target(capsys):
    """The old code's Newton did not converge here (exit 1)."""
    assert main(["orbit", "--k", "18", "--tau", "10", "--delta", "1e-6", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert abs(out["period"] - 3.4608) < 1e-4 and out["slips"] == 3
    # |mu| 0.999991 (0.9999913 at dt = 0.005 too), 9e-6 inside: 40 times the flow
    # multiplier's error (2e-7)
    assert out["stable"] and out["stability"] == "stable"
    assert sum(abs(m - 1) < 1e-3 for m in out["moduli"]) == 5  # the flow's and 2 (3 - 1)


def test_slips_from_the_single_slip_orbit(capsys):
    assert main(["orbit", "--k", "18", "--tau", "10", "--delta", "1", "--slips", "2"]) == 0
    text = capsys.readouterr().out
    assert "period 5.19088" in text and "equally spaced 2-slip orbit" in text


def test_a_multiplier_on_the_circle_is_marginal(capsys):
    """The 2-slip orbit at k = 20 has the multiplier -1.00000000 (the old output said
    "stable", 0 outside the circle)."""
    assert main(["orbit", "--k", "20", "--tau", "10", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["slips"] == 2 and out["stability"] == "marginal" and not out["stable"]


def test_bad_slips_names_the_field(capsys):
    assert main(["orbit", "--k", "18", "--tau", "10", "--slips", "0"]) == 2
    assert "slips = '0'" in capsys.readouterr().err


def test_from_a_stored_run(db, db_url, capsys):
    """The run's final state (Euler dt 1e-3, t = 300, three unequal slips a return) and its
    parameters seed the orbit."""
    spec = {"x": {"param": "k", "start": 18.0, "stop": 18.0, "num": 1},
            "y": {"param": "tau", "start": 10.0, "stop": 10.0, "num": 1},
            "solver": {"method": "euler", "dt": 1e-3, "t_end": 300.0, "window": 100.0,
                       "lyap": False},
            "initial": [{"delta": 1e-6}]}
    submit(db, parse_spec(spec, submitting=True))
    finish_all(db)
    assert main(["orbit", "--from-run", "1", "--db", db_url, "--slips", "3", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert abs(out["period"] - 3.4608) < 1e-4 and out["params"]["k"] == 18.0
    assert main(["orbit", "--from-run", "99", "--db", db_url]) == 2
    assert "from-run" in capsys.readouterr().err
