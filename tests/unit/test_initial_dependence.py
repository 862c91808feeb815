"""Delta-dependence maps (slopetui.sweeps.initial_dependence): cells that agree keep their
regime, cells that differ are DEPENDS, and the band between the fold of cycles and the
Hopf point is counted against them."""

from __future__ import annotations

import math
from dataclasses import replace

from core.fold_curve import FoldPoint
from core.regimes import DEPENDS
from slopetui.plots.sweep_diagram import render_sweep
from slopetui.reproduce.delta_maps import delta_map, map_lines
from slopetui.sweeps.diagram import RunPoint, SweepDiagram
from slopetui.sweeps.initial_dependence import (
    against_band,
    band_test,
    cells,
    combined,
    condition_notes,
    dependence,
    drawn,
)
from slopetui.sweeps.spec import parse_spec

SPEC = parse_spec({"x": {"param": "k", "start": 1, "stop": 8, "num": 8},
                   "y": {"param": "tau", "start": 5, "stop": 10, "num": 2}})


def _diagram(regime_at) -> SweepDiagram:
    runs = [RunPoint(1 + ix + 8 * iy, ix, iy, float(x), float(y), "done" if regime_at(x, y) else
                     "queued", regime_at(x, y), [], None)
            for iy, y in enumerate(SPEC.y.values()) for ix, x in enumerate(SPEC.x.values())]
    return SweepDiagram(1, "test", SPEC, runs)


def near_regime(k, tau):   # delta = 1e-6: rests below the Hopf point (k = 6.1 here)
    return "sliding" if k < 6.1 else "oscillatory"


def far_regime(k, tau):    # delta = 0.1: reaches the cycle from k = 4 at tau = 10 only
    return "oscillatory" if k >= 6.1 or (tau == 10 and k >= 4) else "sliding"


def test_cells_agree_or_depend():
    both = cells([_diagram(near_regime), _diagram(far_regime)])
    verdicts = {(c.x, c.y): c.verdict for c in both}
    assert verdicts[(2.0, 10.0)] == "sliding" and verdicts[(7.0, 5.0)] == "oscillatory"
    assert [k for (k, t), v in sorted(verdicts.items()) if v == DEPENDS] == [4.0, 5.0, 6.0]
    d = dependence(both)
    assert (d.cells, d.depends) == (16, 3) and math.isclose(d.share, 3 / 16)
    assert d.rows == [(10.0, 4.0, 6.0, 3)]


def test_an_unfinished_cell_has_no_verdict():
    pending = _diagram(lambda k, t: None if k == 3 else near_regime(k, t))
    both = cells([_diagram(near_regime), pending])
    assert {c.x for c in both if c.verdict is None} == {3.0}
    assert dependence(both).cells == 14


def test_the_band_from_fold_points():
    # fold 3.5 and Hopf 6.1 at tau = 10; at tau = 5 the Hopf point is supercritical
    folds = [FoldPoint(5.0, 6.5, None, "supercritical"), FoldPoint(10.0, 6.1, 3.5, "subcritical")]
    inside = band_test(folds)
    assert inside is not None
    assert inside(4.0, 10.0) and not inside(3.0, 10.0) and not inside(4.0, 5.0)
    both = cells([_diagram(near_regime), _diagram(far_regime)])
    b = against_band(both, inside)
    assert (b.depends, b.depends_in_band, b.band_cells, b.outside) == (3, 3, 3, [])
    assert band_test([FoldPoint(5.0, 6.5, None, "supercritical")]) is None


def test_the_combined_map_draws_depends_cells():
    m = combined([_diagram(near_regime), _diagram(far_regime)], "map")
    text = render_sweep(m, width=80, height=24, color=False)
    assert "#" in text and "depends" in text
    lines = map_lines(delta_map("Fig. 5", _diagram(near_regime), _diagram(far_regime),
                                [FoldPoint(10.0, 6.1, 3.5, "subcritical")]))
    assert lines[0].startswith("3 of 16 cells (18.8%)")
    assert "3 of the 3 dependent cells lie in it" in lines[2]


def test_no_band_is_drawn_across_a_supercritical_tau():
    """Folds at tau = 1 and 4 with none at 2: the band exists near 1 and at 4, never
    between 1 and 4 (interpolating across tau = 2 would invent one)."""
    folds = [FoldPoint(1.0, -28.0, 2.9, "subcritical"), FoldPoint(2.0, 26.6, None, "supercritical"),
             FoldPoint(4.0, 45.0, 45.1, "subcritical")]
    inside = band_test(folds)
    assert inside is not None
    assert inside(1.0, 1.0) and not inside(1.0, 1.5) and not inside(30.0, 3.0)
    assert inside(45.05, 4.0) and not inside(45.05, 4.5) and not inside(1.0, 0.5)


def _with(d: SweepDiagram, status: dict[float, str]) -> SweepDiagram:
    """The diagram with the runs at these k (every tau) given a status without a regime."""
    return SweepDiagram(d.id, d.name, d.spec, [
        replace(r, status=status[r.x], regime=None) if r.x in status else r for r in d.runs])


def test_cells_with_failed_or_cancelled_runs_are_drawn_as_such_unless_they_depend():
    """Three starts (the module docstring's rules, the first that holds: pending,
    depends, failed, cancelled, the common regime)."""
    near = _with(_diagram(near_regime), {1.0: "failed", 2.0: "failed", 3.0: "cancelled"})
    far = _with(_diagram(far_regime), {2.0: "cancelled", 4.0: "failed", 5.0: "queued",
                                       7.0: "cancelled"})
    third = _with(_diagram(far_regime), {6.0: "failed"})
    m = combined([near, far, third], "map")
    shown = {(r.x, r.y): (r.regime, r.status) for r in m.runs}
    tau5 = {k: shown[(k, 5.0)] for k in range(1, 9)}
    assert tau5 == {1: (None, "failed"),       # the others agree: still not their regime
                    2: (None, "failed"),       # failed before cancelled
                    3: (None, "cancelled"),
                    4: (None, "failed"),
                    5: (None, "queued"),       # a run still to come: pending
                    6: (None, "failed"),
                    7: (None, "cancelled"),
                    8: ("oscillatory", "done")}
    # at tau = 10 the far starts oscillate from k = 4, the near one rests: these cells
    # depend, whatever the failed run would have done; k = 5 waits for its queued run
    assert shown[(4.0, 10.0)] == shown[(6.0, 10.0)] == (DEPENDS, "done")
    assert shown[(5.0, 10.0)] == (None, "queued")
    # no verdict for them: the statistics count only the cells with every regime
    both = cells([near, far, third])
    assert [(c.x, c.y) for c in both if c.finished] == [(8.0, 5.0), (8.0, 10.0)]
    assert dependence(both).depends == 0
    text = render_sweep(m, width=80, height=24, color=False)
    assert "! failed (6)" in text and "/ cancelled (4)" in text and "# depends (2)" in text


def test_condition_notes_name_failed_and_cancelled_runs():
    spec = parse_spec({"x": {"param": "k", "start": 1, "stop": 2, "num": 2},
                       "y": {"param": "tau", "start": 5, "stop": 5, "num": 1},
                       "initial": [{"delta": 1e-6}, {"delta": 0.1}]})
    runs = [RunPoint(1, 0, 0, 1.0, 5.0, "done", "sliding", [], None, ic=0),
            RunPoint(2, 1, 0, 2.0, 5.0, "cancelled", None, [], None, ic=0),
            RunPoint(3, 0, 0, 1.0, 5.0, "failed", None, [], "gave up", ic=1),
            RunPoint(4, 1, 0, 2.0, 5.0, "running", None, [], None, ic=1)]
    d = SweepDiagram(1, "t", spec, runs)
    notes = condition_notes(d)
    assert notes[(0, 0)] == "delta 1e-06: sliding, delta 0.1: failed"
    assert notes[(1, 0)] == "delta 1e-06: cancelled, delta 0.1: pending"
    assert [(r.regime, r.status) for r in drawn(d).runs] == [(None, "failed"), (None, "queued")]
