"""Where a one-parameter branch folds: at tau = 5.965229 walking through the turn with
shorter steps and fitting a parabola put the fold 5.5e-6 too low in k (1.9578449, at dt 0.01
and 0.006 alike). Now the point before the turn is corrected onto the fold's minimally
augmented system. The check is independent of both: Newton at fixed k finds a periodic orbit
just above the fold and none just below it."""

from __future__ import annotations

import json

import pytest

from core.continuation import Branch
from core.orbit import OrbitError, PeriodMap
from core.params import Params
from core.shooting import correct
from slopetui.cli import main

pytestmark = pytest.mark.computation  # only computes: beside the slow tiers (tests/xdist_plan.py)

TAU = 5.965229


def _orbit_at(branch: Branch, k: float) -> bool:
    """Does Newton, from the branch's orbit nearest the fold, find an orbit at k?"""
    i = min(range(len(branch.points)), key=lambda j: branch.points[j].value)
    y, _ = branch.states[i]
    n = branch.g0.size
    pm = PeriodMap(Params().with_(tau=TAU, k=k), branch.g0)
    shot = pm.shoot(y[:n], float(y[n]))
    try:
        correct(pm, y[:n].copy(), float(y[n]), y[:n], shot.d_dT, max_steps=40)
    except OrbitError:
        return False
    return True


def test_the_fold_is_where_the_orbits_end(capsys):
    assert main(["continue", "--param", "k", "--from-hopf", "--tau", str(TAU), "--to", "30",
                 "--json"]) == 0
    rec = json.loads(capsys.readouterr().out)
    (fold,) = [b for b in rec["bifurcations"] if b["type"] == "fold"]
    k_fold = fold["value"]
    assert k_fold == pytest.approx(1.9578557, abs=2e-7)
    hopf = rec["hopf"]["value"]
    branch, _ = Branch.from_hopf(Params().with_(tau=TAU), "k", 0.01, 1e-3, 0.02 * 0.08 * hopf,
                                 0.08 * hopf)
    branch.first()
    while branch.points[-1].value > k_fold + 0.05 or len(branch.points) < 3:
        branch.advance(1e-9)
    for _ in range(6):  # past the turn
        branch.advance(1e-9)
    assert _orbit_at(branch, k_fold + 2e-6)
    assert not _orbit_at(branch, k_fold - 2e-6)
    assert not _orbit_at(branch, 1.9578449 + 2e-6)  # where the parabola had put it
