"""The report's delta-dependence maps: each figure's A (delta = 1e-6) and B (delta = 0.1)
panels as one map (slopetui.sweeps.initial_dependence), with the share of cells whose
regime depends on delta, where they lie, and the bistable band between the Hopf point and
the fold of cycles (continuation) drawn over the plane and counted against them.

The fold curve of Fig. 5's (k, tau) plane comes from the orbit analysis; those of the
friction planes (Figs. 6, 8, 9: a, b, c at k = 12) are computed here, at every tau of the
figure's axis up to FOLD_DENSE_TAU and every FOLD_TAU_STRIDE-th beyond (and its last),
and interpolated between.
The (d, tau) plane of Fig. 10 has no fold curve: its Hopf point in d has no starting
guess (core.hopf_start), so its map is drawn without a band.
"""

from __future__ import annotations

from dataclasses import dataclass

from core.fold_curve import FoldPoint, fold_curve
from slopetui.plots.sweep_diagram import render_sweep
from slopetui.reproduce.orbit_analysis import Say
from slopetui.sweeps.diagram import SweepDiagram
from slopetui.sweeps.fold_overlay import curve_of, has_fold_plane, inside
from slopetui.sweeps.initial_dependence import (
    BandAgreement,
    Dependence,
    against_band,
    band_test,
    cells,
    combined,
    dependence,
)

#: The figures whose panels A and B are compared, by preset key stem.
MAP_FIGURES = ("fig5", "fig6", "fig8", "fig9", "fig10")
#: Friction planes: the fold is computed at every tau of the figure's axis up to
#: FOLD_DENSE_TAU, and at every FOLD_TAU_STRIDE-th beyond. At small tau the fold moves
#: fast and enters the planes: every 4th tau (0.1, 4.3, ...) missed that the fold in a is
#: at 2.19 at tau = 1, and the band of Fig. 6 then held no cell, though 4 cells at tau =
#: 1.15 depend on delta there. Beyond, it moves slowly, and costs most (up to ~90 s a
#: tau at 20: every tau of three planes would add half an hour to the report).
FOLD_DENSE_TAU, FOLD_TAU_STRIDE = 5.0, 4
WIDTH, HEIGHT = 100, 30


@dataclass(frozen=True)
class DeltaMap:
    figure: str          # "Fig. 6"
    param: str           # the plane's x parameter
    diagram: SweepDiagram
    dependence: Dependence
    band: BandAgreement | None
    folds: list[FoldPoint]


def friction_folds(near: SweepDiagram, say: Say = None) -> list[FoldPoint]:
    """The fold of cycles in the plane's x parameter (a, b or c) at a subset of its taus."""
    assert near.spec.y is not None
    taus = [float(t) for t in near.spec.y.values()]
    chosen = sorted({*(t for t in taus if t <= FOLD_DENSE_TAU), *taus[::FOLD_TAU_STRIDE],
                     taus[-1]})
    name = near.spec.x.param
    out = []
    for point in fold_curve(near.spec.base, chosen, name=name):
        if say is not None:
            say(f"fold of cycles in {name} at tau = {point.second:.4g}: "
                + (f"{name} = {point.fold:.5g}" if point.fold is not None
                   else f"none ({point.criticality or point.note})"))
        out.append(point)
    return out


def delta_map(figure: str, near: SweepDiagram, far: SweepDiagram,
              folds: list[FoldPoint]) -> DeltaMap:
    both = cells([near, far])
    test = band_test(folds)
    return DeltaMap(figure, near.spec.x.param,
                    combined([near, far], f"{figure}: where delta = 1e-6 and 0.1 differ"),
                    dependence(both), against_band(both, test) if test is not None else None,
                    folds)


def map_text(m: DeltaMap) -> str:
    fold = (inside(m.diagram.spec, *curve_of(m.folds))
            if m.folds and has_fold_plane(m.diagram.spec) else None)
    return render_sweep(m.diagram, width=WIDTH, height=HEIGHT, color=False, fold=fold,
                        title=m.diagram.name)


def map_lines(m: DeltaMap) -> list[str]:
    d = m.dependence
    x = m.param
    out = [f"{d.depends} of {d.cells} cells ({100 * d.share:.1f}%) end in different regimes "
           "from delta = 1e-6 and from delta = 0.1"]
    if d.rows:
        rows = "; ".join(f"tau = {y:.3g}: {x} {lo:.3g}-{hi:.3g} ({n})" for y, lo, hi, n in d.rows[:8])
        out.append(f"where (per tau, the {x} range of those cells): {rows}"
                   + (f" ... ({len(d.rows)} rows of tau)" if len(d.rows) > 8 else ""))
    b = m.band
    if b is None:
        out.append("no bistable band drawn here: "
                   + ("the (d, tau) plane has no fold curve yet" if x == "d"
                      else "no tau of this plane has a fold of cycles (supercritical Hopf "
                           "points, or the band lies outside the plane)"))
        return out
    out.append(f"the bistable band (between the Hopf point and the fold of cycles in {x}, by "
               f"continuation; `•` marks the fold) holds {b.band_cells} cells; "
               f"{b.depends_in_band} of the {b.depends} dependent cells lie in it"
               + (f", and {100 * b.band_share:.0f}% of the band's cells depend on delta"
                  if b.band_cells else ""))
    if b.outside:
        shown = "; ".join(f"{x} = {c.x:.3g}, tau = {c.y:.3g}: {c.regimes[0]} / {c.regimes[1]}"
                          for c in b.outside[:5])
        out.append(f"dependent outside the band ({len(b.outside)}): {shown}"
                   + (" ..." if len(b.outside) > 5 else ""))
    return out


def maps_section(maps: list[DeltaMap]) -> str:
    out = ["## Where the initial state decides: delta-dependence maps", "",
           "Each figure's two panels as one map: a cell shows its regime where delta = 1e-6 "
           "and delta = 0.1 agree, and `#` where they end in different regimes, the paper's "
           "conditionally stable slopes (`slopetui.sweeps.initial_dependence`). Where "
           "continuation found a fold of cycles, the band between it and the Hopf curve is "
           "where a stable cycle and the stable steady state coexist; cells there depend on "
           "delta only when the two offsets fall on different sides of the basin boundary.",
           ""]
    for m in maps:
        out += [f"### {m.figure}", "", *[f"- {line}" for line in map_lines(m)], "",
                "```text", map_text(m).rstrip(), "```", ""]
    return "\n".join(out)
