"""``continue --param2``'s flags: each bad one refused with its name and range, before
anything is computed."""

from __future__ import annotations

import pytest

from core.params import ParameterError, Params
from slopetui.cli import main
from slopetui.sweeps.curve_request import curve_spec


def _spec(**kw):
    args = {"params": Params().with_(tau=10.0), "dt": 0.01, "param": "k", "param2": "tau",
            "start": "fold", "to2": "2", "points": "300", "step": "0.5"} | kw
    return curve_spec(**args)


def test_a_good_request_is_taken():
    spec = _spec()
    assert (spec.name, spec.second, spec.start, spec.to) == ("k", "tau", "fold", 2.0)
    torus = _spec(start="ns", to="25", hopf_branch=2)
    assert (torus.start, torus.branch_end, torus.hopf_branch) == ("ns", 25.0, 2)


@pytest.mark.parametrize(("kw", "field"), [
    ({"param2": "k"}, "param2"),
    ({"param2": "delta"}, "param2"),
    ({"to2": None}, "to2"),
    ({"to2": "10"}, "to2"),
    ({"to2": "-1"}, "tau"),
    ({"to2": "nan"}, "to2"),
    ({"start": "torus"}, "from"),
    ({"start": "ns"}, "to"),
    ({"start": "ns", "param": "v", "to": "1"}, "param"),
    ({"start": "pd"}, "to"),
    ({"start": "pd", "param": "d", "to": "1"}, "param"),
    ({"param": "d", "start": "hopf"}, "param"),
    ({"points": "1"}, "points"),
    ({"start": "hopf", "points": "3", "to2": "2", "step": "0.5"}, "max-step"),
])
def test_bad_requests_name_their_field(kw, field):
    with pytest.raises(ParameterError) as err:
        _spec(**kw)
    assert err.value.field == field


@pytest.mark.parametrize("argv", [
    ["--from-fold"],
    ["--to2", "3"],
    ["--param2", "tau", "--to2", "3"],
    ["--param2", "tau", "--from-ns", "--to2", "3"],
    ["--param2", "tau", "--from-ns", "0", "--to", "25", "--to2", "3"],
    ["--param2", "tau", "--from-pd", "x", "--to", "25", "--to2", "3"],
    ["--param2", "tau", "--from-fold", "0", "--to2", "3"],
])
def test_the_cli_refuses_before_computing(argv, capsys):
    assert main(["continue", "--param", "k", "--tau", "10", *argv]) == 2
    err = capsys.readouterr().err
    assert err.startswith("slopetui continue: error:") and err.count("\n") == 1
