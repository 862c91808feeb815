"""Warm-started sweeps (core.hysteresis, `slopetui hysteresis`): the state handed over is
exactly the previous point's final state, the growth measured at rest is the leading
characteristic root (theory, core.stability), and the two branches at tau = 10 end within
a grid step of the Hopf point (theory) and of the fold of cycles (continuation)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from core.hysteresis import hysteresis, initial_state, point, settle
from core.orbit import Grid, OrbitError
from core.params import Params
from core.stability import hopf_k, leading_root
from slopetui.cli import main

#: The fold of cycles at tau = 10 found by continuation (core.continuation;
#: tests/unit/test_orbits.py finds it in (1.2, 1.23) and checks it by simulation).
FOLD_TAU10 = 1.2139


def test_the_state_handed_over_is_exactly_the_final_state():
    """Two points of T each from one state end where one point of 2T ends, to the bit:
    the handover adds nothing."""
    p = Params(k=8.0, tau=2.0)
    g = Grid.of(p, 0.01)
    whole, _, _, _ = settle(p, g, initial_state(p, g), 200.0, 50.0)
    half, _, _, _ = settle(p, g, initial_state(p, g), 100.0, 50.0)
    again, _, _, _ = settle(p, g, half, 100.0, 50.0)
    np.testing.assert_array_equal(again, whole)
    pt, handed = point(p, g, half, "k", 100.0, 50.0)
    np.testing.assert_array_equal(handed, whole)
    assert pt.value == 8.0 and not pt.jumped


@pytest.mark.parametrize("k", [6.0, 6.1, 6.2, 6.3])
def test_growth_at_rest_is_the_leading_root(k):
    """Near the Hopf point the rates are ~1e-5 per unit time and change sign at k_H: the
    tangent's envelope gives them to 2e-6 (the noise d = 1e-4 moves the root by ~2e-6,
    which theory without it does not see)."""
    p = Params(k=k, tau=10.0)
    g = Grid.of(p, 0.01)
    _, _, _, growth = settle(p, g, initial_state(p.with_(delta=1e-6), g), 6000.0, 1000.0)
    assert growth == pytest.approx(leading_root(p).real, abs=4e-6)


@pytest.mark.slow
def test_the_branches_end_at_the_hopf_point_and_at_the_fold():
    """tau = 10, k from 1 to 6.6 in steps of 0.4: up, the rest state loses its stability
    between 5.8 and 6.2 (k_H = 6.1485) and the branch jumps to the large cycle; down, the
    cycle lasts to 1.4 and is gone at 1.0 (the fold is at 1.2139)."""
    h = hysteresis(Params(tau=10.0), "k", 1.0, 6.6, 15)
    step = 0.4
    k_h = hopf_k(10.0, Params().F1)
    assert h.onset is not None and h.offset is not None  # the grid's brackets
    onset, offset = h.onset.after, h.offset.after
    assert onset - step < k_h <= onset and h.onset.before == pytest.approx(onset - step)
    assert offset < FOLD_TAU10 <= offset + step and h.offset.before == pytest.approx(offset + step)
    assert all(p.stable_rest for p in h.up if p.value < onset)
    kicked = [p for p in h.up if p.jumped]
    assert [p.value for p in kicked] == [onset] and kicked[0].growth > 0
    assert all(p.regime == "oscillatory" for p in h.down if p.value > offset)
    assert h.down[-1].stable_rest
    # between them both outcomes: the bistable band, by simulation alone
    both = [(u, d) for u, d in zip(h.up, h.down[::-1], strict=True) if u.value == d.value
            and u.regime != d.regime]
    assert {round(u.value, 6) for u, _ in both} == {round(1.4 + 0.4 * i, 6) for i in range(12)}


def test_tau_cannot_be_followed():
    with pytest.raises(OrbitError, match="tau"):
        hysteresis(Params(), "tau", 1.0, 2.0, 3)


def test_the_cli_json_has_the_documented_keys(capsys):
    assert main(["hysteresis", "--param", "k", "--from", "8", "--to", "12", "--points", "3",
                 "--tau", "2", "--t-settle", "300", "--window", "100", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert {"up", "down", "onset_up", "offset_down", "param"} <= set(out)
    assert [p["value"] for p in out["up"]] == [8.0, 10.0, 12.0]
    assert [p["value"] for p in out["down"]] == [12.0, 10.0, 8.0]
    assert all({"value", "regime", "amplitude"} <= set(p) for p in out["up"] + out["down"])


@pytest.mark.parametrize("args,field", [
    (["--param", "k", "--from", "x", "--to", "8"], "from"),
    (["--param", "k", "--from", "1", "--to", "-2"], "k"),
    (["--param", "k", "--from", "1", "--to", "1"], "to"),
    (["--param", "k", "--from", "1", "--to", "8", "--points", "1"], "points"),
    (["--param", "k", "--from", "1", "--to", "8", "--t-settle", "5"], "t-settle"),
    (["--param", "k", "--from", "1", "--to", "8", "--window", "1e9"], "window"),
])
def test_bad_input_names_the_field(args, field, capsys):
    assert main(["hysteresis", *args]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and f"{field} = " in captured.err


def test_unknown_parameters_are_refused_by_the_parser(capsys):
    with pytest.raises(SystemExit):
        main(["hysteresis", "--param", "tau", "--from", "1", "--to", "2"])
    assert "invalid choice" in capsys.readouterr().err
