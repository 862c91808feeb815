"""Where the initial state decides: the same lattice computed from several initial
conditions, cell by cell.

A cell whose runs all end in one regime shows that regime; a cell whose runs disagree is
``DEPENDS``: its fate depends on the initial state, the paper's *conditionally stable*
slope. The paper compares its phase diagrams at delta = 1e-6 and delta = 0.1 by eye (Figs.
5-10, A against B); here the two lattices are one map. The band where a stable cycle and
the stable steady state coexist (between the Hopf curve and the fold of cycles, from
continuation: core.fold_curve) is where such cells are expected; ``band_test`` builds
that test from fold points.

A cell with runs that will give no regime (run status failed or cancelled) is drawn
(``combined``) by the first of these that holds:

1. a run is still queued or running: pending, as any unfinished cell (it may yet turn
   out to depend);
2. the done runs disagree: ``DEPENDS``, which the missing regimes cannot undo;
3. a run failed: failed, although the done runs agree (the failed condition might have
   ended elsewhere, so their regime would claim more than was computed; "failed" first,
   as the finding to look into);
4. a run was cancelled: cancelled, likewise;
5. otherwise the common regime.

Such a cell has no ``verdict`` and does not count as finished: ``dependence`` and
``against_band`` count only the cells with a regime from every condition.

No UI and no SQL: the report, ``show`` and the application draw what this computes.
"""

from __future__ import annotations

from bisect import bisect_right
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

from core.regimes import DEPENDS
from slopetui.sweeps.diagram import RunPoint, SweepDiagram

if TYPE_CHECKING:
    from core.fold_curve import FoldPoint

__all__ = ["DEPENDS", "BandAgreement", "Cell", "Dependence", "against_band", "band_test",
           "cells", "combined", "condition_notes", "dependence", "drawn", "per_condition"]


#: Run statuses (slopetui.store.statuses) of runs that will never have a regime, in the
#: order a cell's drawing prefers them (module docstring).
NO_RESULT: tuple[str, ...] = ("failed", "cancelled")


@dataclass(frozen=True)
class Cell:
    """One lattice point: its position, values, and the regime each initial condition
    ended in (None: not finished, failed or cancelled), with its run's status ("queued"
    for a condition without a run; empty: statuses unknown, every None is pending)."""

    ix: int
    iy: int
    x: float
    y: float | None
    regimes: tuple[str | None, ...]
    statuses: tuple[str, ...] = ()

    @property
    def finished(self) -> bool:
        return all(r is not None for r in self.regimes)

    @property
    def verdict(self) -> str | None:
        """The common regime, DEPENDS, or None while a run is not finished."""
        if not self.finished:
            return None
        return self.regimes[0] if len(set(self.regimes)) == 1 else DEPENDS

    @property
    def drawn(self) -> tuple[str | None, str]:
        """(regime, run status) a drawing shows for the cell (the module docstring's
        rules): (regime or DEPENDS, "done"), (None, "failed" | "cancelled"), or
        (None, "queued") while pending."""
        statuses = self.statuses or ("done",) * len(self.regimes)
        ended = [s for r, s in zip(self.regimes, statuses, strict=True)
                 if r is None and s in NO_RESULT]
        if sum(r is None for r in self.regimes) > len(ended):  # some run is still to come
            return None, "queued"
        regimes = {r for r in self.regimes if r is not None}
        if len(regimes) > 1:
            return DEPENDS, "done"
        for status in NO_RESULT:
            if status in ended:
                return None, status
        return regimes.pop(), "done"


def cells(diagrams: Sequence[SweepDiagram]) -> list[Cell]:
    """The cells of lattices that share their axes (one diagram per initial condition),
    in the first one's order; a cell missing from any is not finished."""
    by = [{(r.ix, r.iy): r for r in d.runs} for d in diagrams]
    out = []
    for r in diagrams[0].runs:
        mine = [b.get((r.ix, r.iy)) for b in by]
        out.append(Cell(r.ix, r.iy, r.x, r.y, tuple(m.regime if m else None for m in mine),
                        tuple(m.status if m else "queued" for m in mine)))
    return out


def combined(diagrams: Sequence[SweepDiagram], name: str) -> SweepDiagram:
    """One diagram whose runs carry what each cell is drawn as (``Cell.drawn``: its
    verdict as their regime, or failed, cancelled or queued as their status; the first
    lattice's runs otherwise): what the phase-diagram drawings take."""
    shown = {(c.ix, c.iy): c.drawn for c in cells(diagrams)}
    first = diagrams[0]
    runs = [_as_drawn(r, *shown[(r.ix, r.iy)]) for r in first.runs]
    return SweepDiagram(first.id, name, first.spec, runs)


def per_condition(d: SweepDiagram) -> list[SweepDiagram]:
    """A sweep with initial conditions (spec [[initial]]) as one diagram per condition."""
    n = len(d.spec.conditions)
    return [SweepDiagram(d.id, d.name, d.spec, [r for r in d.runs if r.ic == i])
            for i in range(n)]


def drawn(d: SweepDiagram) -> SweepDiagram:
    """What a drawing of the sweep shows: the sweep itself, or with two or more initial
    conditions their map (each cell's common regime, DEPENDS, or failed, cancelled or
    pending: ``Cell.drawn``)."""
    if len(d.spec.conditions) < 2:
        return d
    return combined(per_condition(d), d.name)


def condition_notes(d: SweepDiagram) -> dict[tuple[int, int], str]:
    """Per cell of a sweep with two or more initial conditions, what each one ended in
    ("delta 1e-06: sliding, delta 0.1: oscillatory"; the history too where it is not
    the constant one); empty for a sweep of one."""
    conditions = d.spec.conditions
    if len(conditions) < 2:
        return {}
    names = [f"delta {delta:g}" + ("" if history == "constant" else f" {history}")
             for delta, history in conditions]
    out: dict[tuple[int, int], list[str]] = {}
    for r in sorted(d.runs, key=lambda r: r.ic):
        outcome = r.regime or (r.status if r.status in NO_RESULT else "pending")
        out.setdefault((r.ix, r.iy), []).append(f"{names[r.ic]}: {outcome}")
    return {cell: ", ".join(parts) for cell, parts in out.items()}


def _as_drawn(r: RunPoint, regime: str | None, status: str) -> RunPoint:
    return replace(r, regime=regime, status=status, inferred=False)


@dataclass(frozen=True)
class Dependence:
    """How much of a lattice depends on the initial state: finished cells, those that
    depend, and per row of y (tau) the x range the dependent cells span."""

    cells: int
    depends: int
    rows: list[tuple[float, float, float, int]]  # (y, x min, x max, count)

    @property
    def share(self) -> float:
        return self.depends / self.cells if self.cells else float("nan")


def dependence(all_cells: Sequence[Cell]) -> Dependence:
    done = [c for c in all_cells if c.finished]
    dep = [c for c in done if c.verdict == DEPENDS]
    rows: dict[float, list[float]] = {}
    for c in dep:
        if c.y is not None:
            rows.setdefault(c.y, []).append(c.x)
    return Dependence(len(done), len(dep), [(y, min(xs), max(xs), len(xs))
                                            for y, xs in sorted(rows.items())])


#: Is (x, tau) inside the bistable band?
BandTest = Callable[[float, float], bool]


def band_test(folds: Sequence[FoldPoint]) -> BandTest | None:
    """Between the fold of cycles and the Hopf point, both interpolated linearly in tau
    between two neighbouring computed taus that both have a fold; no band outside the
    computed taus, nor between two taus of which one has none (a supercritical Hopf
    point: at k = 12 the fold in a exists at tau = 1.15, not at 2.2 and 3.2, again from
    4.3). None when no tau has a fold. The band lies on either side of the Hopf point
    (below it in k, above it in a and c)."""
    points = sorted((f.second, f.fold, f.hopf) for f in folds)
    if not any(fold is not None for _, fold, _ in points):
        return None
    taus = [t for t, _, _ in points]

    def inside(x: float, tau: float) -> bool:
        i = bisect_right(taus, tau) - 1  # taus[i] <= tau
        if i < 0 or (taus[i] != tau and i + 1 == len(taus)):
            return False
        (t0, f0, h0), (t1, f1, h1) = points[i], points[i] if taus[i] == tau else points[i + 1]
        if f0 is None or f1 is None:
            return False
        w = 0.0 if t1 == t0 else (tau - t0) / (t1 - t0)
        fold, hopf = f0 + w * (f1 - f0), h0 + w * (h1 - h0)
        return min(fold, hopf) < x < max(fold, hopf)

    return inside


@dataclass(frozen=True)
class BandAgreement:
    """Dependent cells against the band: how many lie in it, how many cells the band
    holds and what share of them depend, and the dependent cells outside it."""

    depends: int
    depends_in_band: int
    band_cells: int
    outside: list[Cell]

    @property
    def band_share(self) -> float:
        return self.depends_in_band / self.band_cells if self.band_cells else float("nan")


def against_band(all_cells: Sequence[Cell], inside: BandTest) -> BandAgreement:
    def in_band(c: Cell) -> bool:
        return c.y is not None and inside(c.x, c.y)

    done = [c for c in all_cells if c.finished and c.y is not None]
    dep = [c for c in done if c.verdict == DEPENDS]
    return BandAgreement(len(dep), sum(in_band(c) for c in dep), sum(in_band(c) for c in done),
                         [c for c in dep if not in_band(c)])
