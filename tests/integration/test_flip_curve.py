"""The period doubling continued as a curve (core.flip_continuation): from the one real
period doubling found on this model's branches (b = 22.32519 at tau = 2, k = 12, dt =
0.0025: tests/integration/test_real_crossings.py locates it by regula falsi on the
multiplier and checks it by direct simulation) into (b, k). Every point of the curve is a
period doubling by the Floquet solver's own count (ARPACK on the monodromy: a multiplier
at -1), a method apart from the bordered system the curve solves."""

from __future__ import annotations

import json

import numpy as np

from slopetui.cli import main

ASK = ["continue", "--param", "b", "--param2", "k", "--from-pd", "--tau", "2", "--k", "12",
       "--to", "22.335", "--to2", "12.1", "--dt", "0.0025", "--max-step", "0.05", "--json"]


def test_the_period_doubling_curve_keeps_a_multiplier_at_minus_one(capsys):
    from core.curve_start import CurveSpec, start
    from core.params import Params

    assert main(ASK) == 0
    rec = json.loads(capsys.readouterr().out)
    assert rec["start"] == "pd" and rec["end"] == "reached k = 12.1"
    first, last = rec["curve"][0], rec["curve"][-1]
    assert abs(first["b"] - 22.32519) < 2e-5 and first["k"] == 12.0
    assert last["k"] == 12.1 and last["b"] > first["b"]
    assert abs(first["period"] - 4.01147) < 1e-4
    assert rec["solver"]["curve"] == "pd" and rec["params"]["b"] == first["b"]

    walk = start(CurveSpec(Params(tau=2.0, k=12.0), "b", "k", "pd", 0.0025, 12.1, 20, 0.05,
                           branch_end=22.335))
    points = []
    while (p := walk.step()) is not None:
        points.append(p)
    assert len(points) == len(rec["curve"]) >= 3
    for p, shown in zip(points, rec["curve"], strict=True):
        assert p.multipliers is not None
        mu = p.multipliers.nontrivial
        assert np.min(np.abs(mu + 1.0)) < 1e-6, (p.first, p.second, mu)
        assert p.first == shown["b"]
    assert walk.found() == []


def test_continue_switches_onto_the_period_doubled_branch(capsys):
    """`continue --switch-pd`: at the branch's period doubling the orbits of twice the period
    (period ~2T), which leave the old orbit traversed twice (their distance to their own
    half-period shift grows from zero) and come back to it at a period doubling (the bubble
    between b = 22.32519 and 22.33167 that test_real_crossings.py finds)."""
    assert main(["continue", "--param", "b", "--from-hopf", "--tau", "2", "--k", "12",
                 "--to", "22.335", "--dt", "0.0025", "--points", "120", "--switch-pd",
                 "--json"]) == 0
    rec = json.loads(capsys.readouterr().out)
    pds = [b for b in rec["bifurcations"] if b["type"] == "period-doubling"]
    doubled = rec["doubled"]
    assert doubled["at"] == pds[0] and abs(pds[0]["value"] - 22.32519) < 2e-5
    points = doubled["branch"]
    assert len(points) > 5
    assert abs(points[0]["period"] - 2 * pds[0]["period"]) < 1e-2
    shifts = [p["half_shift"] for p in points]
    assert shifts[0] < 0.1 and max(shifts) > 1.0  # it leaves the doubled orbit ...
    top = shifts.index(max(shifts))
    i = next(j for j in range(top, len(points)) if shifts[j] < 0.1 * max(shifts))
    # ... and comes back to it at a period doubling of the old branch (one end of the
    # bubble or the other: which one the walk reaches first depends on its steps)
    lo, hi = sorted((points[i - 1]["value"], points[i]["value"]))
    assert any(lo - 1e-3 < b["value"] < hi + 1e-3 for b in pds), (points[i - 1], points[i])
