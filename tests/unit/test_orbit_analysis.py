"""The report's continuation analysis: the band against two panels, and its section."""

from __future__ import annotations

import math
from types import SimpleNamespace

import pytest

from core.fold_curve import FoldPoint
from slopetui.reproduce.findings import basin_sentence
from slopetui.reproduce.orbit_analysis import OrbitAnalysis, Tau10, band_comparison, tau10
from slopetui.reproduce.report import orbit_section

FOLDS = [FoldPoint(5.0, 6.6, 3.0, "subcritical"), FoldPoint(15.0, 6.0, 1.0, "subcritical"),
         FoldPoint(0.2, 300.0, None, "supercritical", "no turn within the search")]


def _panel(cells):
    runs = [SimpleNamespace(ix=i, iy=0, x=k, y=tau, regime=regime,
                            status="done" if regime else "queued")
            for i, (k, tau, regime) in enumerate(cells)]
    return SimpleNamespace(runs=runs)


def test_the_band_counts_disagreements_inside_and_out():
    # at tau = 10 the band is 2 < k < 6.3 (interpolated between tau = 5 and 15)
    near = _panel([(4.0, 10.0, "sliding"), (5.0, 10.0, "oscillatory"), (8.0, 10.0, "sliding"),
                   (1.0, 10.0, "sliding"), (4.0, 0.1, "sliding")])
    far = _panel([(4.0, 10.0, "oscillatory"), (5.0, 10.0, "oscillatory"), (8.0, 10.0, "oscillatory"),
                  (1.0, 10.0, "sliding"), (4.0, 0.1, "oscillatory")])
    b = band_comparison(near, far, FOLDS)
    assert (b.cells, b.disagree, b.disagree_in_band, b.band_cells) == (5, 3, 1, 2)
    assert b.band_disagree_share == 0.5
    assert {(k, t) for k, t, _, _ in b.outside} == {(8.0, 10.0), (4.0, 0.1)}


def test_the_section_shows_the_fold_table_and_the_band():
    t10 = Tau10(6.146, 10.573, "subcritical", [], (0.64, 0.73), [], [], 3,
                [(3.0, 0.1, False), (3.0, 1.0, True)])
    near = _panel([(4.0, 10.0, "sliding")])
    far = _panel([(4.0, 10.0, "oscillatory")])
    text = orbit_section(OrbitAnalysis(t10, FOLDS, band_comparison(near, far, FOLDS), 1.0))
    assert "| 5 | 6.60000 | 3.00000 | subcritical |" in text
    assert "none (no turn within the search)" in text
    assert "in the bistable band" in text and "subcritical" in text
    assert "k = 3: 0.1 rest, 1 cycle" in text
    k, tau = OrbitAnalysis(t10, FOLDS, None, 0.0).curve()
    assert list(k) == [3.0, 1.0] and list(tau) == [5.0, 15.0]


@pytest.mark.slow
def test_tau10_finds_the_fold_and_checks_it_by_simulation():
    t = tau10()
    assert t.criticality == "subcritical" and t.fold is not None and 1.2 < t.fold < 1.23
    assert [c.stays for c in t.checks] == [True, False]
    assert not math.isnan(t.leading[0]) and t.leading[1] < 1
    assert t.pulses[0].distance < 0.1  # k = 15: the simulation reaches the single-slip orbit
    assert all(p.simulated_maxima >= 2 and p.distance > 0.5 for p in t.pulses[1:])


def test_the_fold_curve_is_drawn_inside_the_plane_only(db):
    """The fold table goes on to tau = 60; over a plane that ends at tau = 10 those points
    must not stretch the axis (the first regenerated report drew Fig. 5 up to tau = 60)."""
    from slopetui.reproduce.report import diagram_text
    from slopetui.sweeps.diagram import load_diagram
    from slopetui.sweeps.spec import parse_spec
    from slopetui.sweeps.submit import submit
    from tests.support import QUICK_SOLVER, finish_all
    spec = parse_spec({"x": {"param": "k", "start": 0.5, "stop": 8, "num": 3},
                       "y": {"param": "tau", "start": 4, "stop": 10, "num": 2},
                       "solver": QUICK_SOLVER})
    sweep = submit(db, spec).sweep_id
    finish_all(db)
    t10 = Tau10(6.146, 10.573, "subcritical", [], (0.64, 0.73), [], [], 3, [])
    folds = [FoldPoint(5.0, 6.6, 2.3, "subcritical"), FoldPoint(60.0, 5.97, 0.36, "subcritical")]
    text = diagram_text(load_diagram(db, sweep), OrbitAnalysis(t10, folds, None, 0.0))
    labels = [float(line.split("┤")[0]) for line in text.splitlines()
              if "┤" in line and line.split("┤")[0].strip()]
    assert "fold of cycles" in text and labels and max(labels) <= 10.5


@pytest.mark.slow  # two continuations to their folds: 5-12 s, out of the fast loop
def test_the_fold_curve_says_each_tau_as_it_goes():
    """The report's analysis takes minutes; each fold is said when found."""
    from core.params import Params
    from slopetui.reproduce.orbit_analysis import folds_over_tau
    said: list[str] = []
    folds = folds_over_tau(Params(delta=0.1), [10.0, 5.0], said.append)
    assert [f.second for f in folds] == [5.0, 10.0]
    assert said == [f"fold of cycles at tau = {f.second:.4g}: k = {f.fold:.5g}" for f in folds]


def test_the_band_counts_where_each_offset_reaches_the_cycle():
    """Fig. 5's "both delta start in the rest basin" was false next to the Hopf curve; the
    sentence follows the counts of each panel's moving band cells."""
    near = _panel([(3.0, 10.0, "sliding"), (5.0, 10.0, "sliding"), (6.0, 10.0, "sliding"),
                   (8.0, 10.0, "oscillatory")])
    far = _panel([(3.0, 10.0, "sliding"), (5.0, 10.0, "oscillatory"), (6.0, 10.0, "oscillatory"),
                  (8.0, 10.0, "oscillatory")])
    b = band_comparison(near, far, FOLDS)
    assert b.band_cells == 3 and b.moving_in_band == (0, 2)
    assert b.far_moves == [(6.0, 10.0), (5.0, 10.0)]
    text = basin_sentence(b)
    assert "delta = 1e-6 reaches the cycle in 0 cells and delta = 0.1 in 2" in text
    assert "outside the fixed point's basin" in text and "e.g. k = 6, tau = 10; k = 5" in text
    assert "both offsets start in the fixed point's basin" not in text
    resting = band_comparison(near, _panel([(3.0, 10.0, "sliding"), (5.0, 10.0, "sliding"),
                                            (6.0, 10.0, "sliding"), (8.0, 10.0, "sliding")]),
                              FOLDS)
    assert "both offsets start in the fixed point's basin everywhere" in basin_sentence(resting)


@pytest.mark.slow
def test_next_to_the_hopf_point_delta_01_lands_on_the_cycle():
    """The case a referee named, against linear theory and a finer scheme than the paper's:
    k = 6.05 < k_H(10) = 6.1462 (the fixed point is linearly stable), yet delta = 0.1 of
    eq. 19 ends on the cycle, while delta = 1e-6 decays to rest (RK4, dt 0.01; the growth
    away from rest is slow: at t = 4000 the run still spirals out, at 2e4 it is there)."""
    from core.params import Params
    from core.point import run_point
    from core.solve import SolverSettings
    from core.stability import leading_exponent

    s = SolverSettings(method="rk4", dt=0.01, t_end=20000.0, window=1000.0, lyap=False)
    assert leading_exponent(Params(k=6.05, tau=10.0)) < 0
    assert run_point(Params(k=6.05, tau=10.0, delta=0.1), s).summary.regime == "oscillatory"
    assert run_point(Params(k=6.05, tau=10.0, delta=1e-6), s).summary.regime == "sliding"
