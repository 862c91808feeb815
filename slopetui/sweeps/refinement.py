"""The geometry of an adaptive phase diagram, as pure functions of (lattice shape, levels,
known labels): which points to compute at each level, and the labels of the points
never computed. ``slopetui.sweeps.adaptive`` drives it against the store; the tests
drive it against synthetic label functions.

**The lattice** is the sweep's own grid, ``nx x ny`` points (any ``num >= 2``), indexed
``(ix, iy)``. Along each axis of ``n`` points, level 0 holds every ``2**levels``-th index
*and* the last one (``n - 1``), so ``n`` need not be ``2**levels * m + 1``; level ``l + 1``
adds the middle index ``(a + b) // 2`` of every interval ``[a, b]`` of level ``l`` longer
than 1. An interval of at most ``2**levels`` steps is down to single steps after
``levels`` halvings (a short last interval sooner), so level ``levels`` is the final
resolution on both axes. The lines of a level are global: a *cell* of level ``l`` is the
rectangle between neighbouring lines of level ``l`` on both axes, and the 8 cells around
it are its neighbours at the same level.

**The rule.** The cells of level 0 (all of them) are *active*. After level ``l`` is
computed, an active cell whose 4 corner labels are not all equal is *flagged* (the
label is the regime; a failed run counts as its own label, ``failed``). The flagged
cells and their 8 neighbours (the one-cell halo) are *split*: every lattice point of
their level-``l + 1`` sub-lattice (corners, edge midpoints, centre) that is not known
yet is queued as level ``l + 1``, and their sub-cells are the active cells of level
``l + 1``. Refinement ends after level ``levels`` (nothing can be split further) or when
no active cell is flagged. A level may queue nothing (every point it needs is known);
it still counts as a level, so that its own flags are looked at.

Decisions, and why:

- *A halo cell need not be active.* The neighbour of a flagged cell may lie inside a
  cell that was uniform one level up and was not split, so some of its corners were
  never computed. Its corners are then queued with its midpoints (at most 9 points
  instead of 5). Restricting the halo to active cells would stop refinement at the edge
  of the refined region, and a boundary that leaves that region between two coarse
  corners (a thin tongue of a regime) would be cut off there.
- *Decisions use only the corners of active cells*, which are known when the level is
  complete; points computed later never change an earlier decision. So the history of
  a sweep can be replayed from its final labels alone: the store keeps no per-cell state,
  only each run's label and the sweep's current level.
- *The fill.* A lattice point that was never computed takes the label of the finest
  active cell that contains it. That cell was not split (else its sub-cells, finer,
  would contain the point), so it was not flagged: its 4 corners agree. A point on the
  edge between a uniform cell and a refined neighbour: the neighbour's refinement may
  have computed it (computed values always win), else the neighbour's finer sub-cell
  containing it decides. Two uniform cells of one level that share an edge share two
  corners, hence their label, so the finest level never disagrees with itself.
- *What it cannot see:* a region that touches no computed point. Each level's halo
  reaches one cell of that level beyond the cells it flags, so a thin feature that no
  coarse point sees is followed only a few lattice steps out of a refined region (a
  tongue between lattice lines: ``tests/unit/test_adaptive.py``), and an island smaller
  than a coarse cell, away from every boundary, is missed. The coarse spacing
  (``levels``) bounds the size of what can be missed.
- *What it costs:* the coarse lattice, plus about 12 points per lattice step of
  boundary (the flagged cells of 2 steps and their halo make a band 6 points wide that
  is computed whole; the coarser levels' bands are wider but sparser). The saving grows
  with the lattice: a boundary of length ~n costs ~12 n of the n**2 points.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

#: The label of a failed run: its own label, so that a failure flags its cells.
FAILED = "failed"

Point = tuple[int, int]


class RefinementError(RuntimeError):
    """The known labels do not fit the level: a corner of an active cell is unknown."""


def axis_lines(n: int, levels: int) -> list[np.ndarray]:
    """The lattice indices along an axis of ``n`` points at levels 0..levels (sorted)."""
    if n < 2:
        raise ValueError(f"an adaptive axis needs at least 2 points, got {n}")
    first = np.union1d(np.arange(0, n, 2 ** levels), [n - 1])
    lines = [first]
    for _ in range(levels):
        prev = lines[-1]
        mids = (prev[:-1] + prev[1:]) // 2
        lines.append(np.union1d(prev, mids[np.diff(prev) > 1]))
    return lines


@dataclass(frozen=True)
class LevelPlan:
    """What level ``level`` needs: every lattice point of its active cells (``required``)
    and those of them not known yet (``new``, to be computed)."""

    level: int
    required: list[Point]
    new: list[Point]


class Refinement:
    """The replayed refinement of an ``nx x ny`` lattice from the labels known so far.

    ``labels`` maps lattice points to labels (regimes, or FAILED) of computed runs only.
    ``level`` is the last level whose points are all known: the replay decides levels
    0..level-1 again, exactly as they were decided (see the module docstring).
    """

    def __init__(self, nx: int, ny: int, levels: int, labels: Mapping[Point, str],
                 level: int) -> None:
        if not 0 <= level <= levels:
            raise ValueError(f"level {level} outside 0..{levels}")
        self.nx, self.ny, self.levels, self.level = nx, ny, levels, level
        self.xl, self.yl = axis_lines(nx, levels), axis_lines(ny, levels)
        self.names = sorted(set(labels.values()))
        code = {name: i for i, name in enumerate(self.names)}
        #: Label codes per lattice point, -1 where not known.
        self.codes = np.full((nx, ny), -1, dtype=np.int32)
        for (ix, iy), name in labels.items():
            self.codes[ix, iy] = code[name]
        #: active[l]: the active cells of level l, a (cells along x, cells along y) mask.
        self.active = [np.ones((len(self.xl[0]) - 1, len(self.yl[0]) - 1), dtype=bool)]
        for lv in range(level):
            self.active.append(self._children(lv, self._split(lv)))

    # --- one level --------------------------------------------------------------------
    def _corners(self, lv: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        xs, ys = self.xl[lv], self.yl[lv]
        c = self.codes
        return (c[np.ix_(xs[:-1], ys[:-1])], c[np.ix_(xs[1:], ys[:-1])],
                c[np.ix_(xs[:-1], ys[1:])], c[np.ix_(xs[1:], ys[1:])])

    def _flagged(self, lv: int) -> np.ndarray:
        """Active cells of level lv whose corner labels differ."""
        c00, c10, c01, c11 = self._corners(lv)
        active = self.active[lv]
        unknown = active & ((c00 < 0) | (c10 < 0) | (c01 < 0) | (c11 < 0))
        if unknown.any():
            i, j = np.argwhere(unknown)[0]
            raise RefinementError(
                f"level {lv} is not complete: a corner of cell x {self.xl[lv][i]}.."
                f"{self.xl[lv][i + 1]}, y {self.yl[lv][j]}..{self.yl[lv][j + 1]} is unknown")
        mixed = (c00 != c10) | (c00 != c01) | (c00 != c11)
        return active & mixed

    def _split(self, lv: int) -> np.ndarray:
        """Flagged cells of level lv and their 8 neighbours (the halo)."""
        flagged = self._flagged(lv)
        padded = np.pad(flagged, 1)
        w, h = flagged.shape
        split = np.zeros_like(flagged)
        for dx in (0, 1, 2):
            for dy in (0, 1, 2):
                split |= padded[dx:dx + w, dy:dy + h]
        return split

    def _children(self, lv: int, split: np.ndarray) -> np.ndarray:
        """Active cells of level lv + 1: the sub-cells of the split cells of level lv."""
        px = np.searchsorted(self.xl[lv], self.xl[lv + 1][:-1], side="right") - 1
        py = np.searchsorted(self.yl[lv], self.yl[lv + 1][:-1], side="right") - 1
        return split[np.ix_(px, py)]

    def _points_of(self, lv: int, cells: np.ndarray) -> list[Point]:
        """Every lattice point that is a corner of one of the cells of level lv."""
        need = np.zeros((len(self.xl[lv]), len(self.yl[lv])), dtype=bool)
        need[:-1, :-1] |= cells
        need[1:, :-1] |= cells
        need[:-1, 1:] |= cells
        need[1:, 1:] |= cells
        i, j = np.nonzero(need)
        return list(zip(self.xl[lv][i].tolist(), self.yl[lv][j].tolist(), strict=True))

    # --- what the driver asks -------------------------------------------------------------
    def next_level(self) -> LevelPlan | None:
        """The plan of level ``level + 1``, or None when refinement is over (the final
        resolution is reached, or no active cell is flagged). Needs level complete."""
        if self.level >= self.levels:
            self._flagged(self.level)  # still check that the level is complete
            return None
        split = self._split(self.level)
        if not split.any():
            return None
        cells = self._children(self.level, split)
        required = self._points_of(self.level + 1, cells)
        new = [p for p in required if self.codes[p] < 0]
        return LevelPlan(self.level + 1, required, new)

    def fill(self) -> dict[Point, tuple[str, int]]:
        """Every lattice point not known: (the label of the finest active cell containing
        it, that cell's level). Call when next_level() is None."""
        label = np.full((self.nx, self.ny), -1, dtype=np.int32)
        depth = np.full((self.nx, self.ny), -1, dtype=np.int32)
        for lv in range(self.level + 1):  # coarse to fine: the finest cell paints last
            c00, *_ = self._corners(lv)
            uniform = self.active[lv] & ~self._flagged(lv)
            # A point on a line of the level lies in the cells on both sides of it: try
            # both (uniform cells of one level that share a point agree on its label).
            for cx in _containing_cells(self.xl[lv], self.nx):
                for cy in _containing_cells(self.yl[lv], self.ny):
                    paint = uniform[np.ix_(cx, cy)]
                    label[paint] = c00[np.ix_(cx, cy)][paint]
                    depth[paint] = lv
        unknown = self.codes < 0
        if (label[unknown] < 0).any():  # the module docstring argues this cannot happen
            raise RefinementError("a point lies in no uniform active cell")
        return {(int(ix), int(iy)): (self.names[label[ix, iy]], int(depth[ix, iy]))
                for ix, iy in np.argwhere(unknown)}


def _containing_cells(lines: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """For every lattice index 0..n-1, the cell (interval between lines) containing it:
    the one above a line point, and the one below it (equal for points between lines)."""
    t = np.arange(n)
    last = len(lines) - 2
    above = np.clip(np.searchsorted(lines, t, side="right") - 1, 0, last)
    below = np.clip(np.searchsorted(lines, t, side="left") - 1, 0, last)
    return above, below


def coarse_points(nx: int, ny: int, levels: int) -> list[Point]:
    """The lattice points of level 0."""
    xs, ys = axis_lines(nx, levels)[0], axis_lines(ny, levels)[0]
    return [(int(ix), int(iy)) for iy in ys for ix in xs]


@dataclass(frozen=True)
class InMemoryResult:
    """A refinement run against a label function: every point's label, which points were
    computed (and at which level), and the levels queued."""

    labels: dict[Point, str]
    computed: dict[Point, int]
    inferred: dict[Point, tuple[str, int]]
    level: int


def refine_in_memory(nx: int, ny: int, levels: int,
                     label_of: Callable[[int, int], str]) -> InMemoryResult:
    """Run the whole refinement with ``label_of(ix, iy)`` standing in for the solver:
    the same protocol as the store's ``advance``, without a store."""
    computed = {p: 0 for p in coarse_points(nx, ny, levels)}
    known = {p: label_of(*p) for p in computed}
    level = 0
    while True:
        plan = Refinement(nx, ny, levels, known, level).next_level()
        if plan is None:
            break
        level = plan.level
        for p in plan.new:
            computed[p] = level
            known[p] = label_of(*p)
    inferred = Refinement(nx, ny, levels, known, level).fill()
    labels = {**known, **{p: lab for p, (lab, _) in inferred.items()}}
    return InMemoryResult(labels, computed, inferred, level)
