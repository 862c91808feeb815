"""What a phase grid draws (``GridData``: a sweep's lattice, its runs' labels, the curves
over it) and where a curve falls on its blocks."""

from __future__ import annotations

import copy
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from slopetui.plots.lattice_cells import CODES, PENDING_CODE, lattice_codes
from slopetui.plots.regime_colors import PENDING, run_key


@dataclass
class GridData:
    """A sweep's grid: axis values and, per (ix, iy), the run id and its label
    (``cell_label``: a regime, DEPENDS, FAILED or CANCELLED; None while not finished)."""

    x_param: str
    y_param: str
    xs: np.ndarray
    ys: np.ndarray
    x_log: bool
    y_log: bool
    runs: dict[tuple[int, int], tuple[int, str | None]] = field(default_factory=dict)
    hopf: tuple[np.ndarray, np.ndarray] | None = None
    #: Adaptive sweeps: the grid points whose run was inferred, not computed.
    inferred: frozenset[tuple[int, int]] = frozenset()
    adaptive: bool = False
    #: The fold-of-cycles curve (k, tau) of a (k, tau) plane, once computed.
    fold: tuple[np.ndarray, np.ndarray] | None = None
    #: A sweep of several initial conditions: per cell, what each one ended in.
    notes: dict[tuple[int, int], str] = field(default_factory=dict)
    #: The labels as a (ny, nx) array of lattice_cells codes, and the inferred points as
    #: a mask of the same shape: made once (by the thread that loads the data), drawn
    #: many times.
    codes: np.ndarray = field(init=False, repr=False)
    inferred_mask: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        nx, ny = len(self.xs), len(self.ys)
        self.codes = lattice_codes({p: label for p, (_, label) in self.runs.items()}, nx, ny)
        self.inferred_mask = np.zeros((ny, nx), dtype=bool)
        for ix, iy in self.inferred:
            self.inferred_mask[iy, ix] = True

    def with_runs(self, runs: Mapping[tuple[int, int], tuple[int, str | None, bool]]
                  ) -> GridData:
        """A copy with these points' runs put in: (run id, label, inferred) by (ix, iy).
        A few runs finished among 10,000: a copy of the arrays and the dict (C loops)
        rather than the whole grid made again."""
        grid = copy.copy(self)  # not made again from its runs (__post_init__)
        grid.runs = dict(self.runs)
        grid.codes, grid.inferred_mask = self.codes.copy(), self.inferred_mask.copy()
        inferred = set(self.inferred)
        for (ix, iy), (run_id, label, was_inferred) in runs.items():
            grid.runs[(ix, iy)] = (run_id, label)
            grid.codes[iy, ix] = PENDING_CODE if label is None else CODES[label]
            grid.inferred_mask[iy, ix] = was_inferred
            (inferred.add if was_inferred else inferred.discard)((ix, iy))
        grid.inferred = frozenset(inferred)
        return grid

    @property
    def n_unqueued(self) -> int:
        """Grid points without a run (an adaptive sweep's levels still to come)."""
        return len(self.xs) * len(self.ys) - len(self.runs)


def cell_label(regime: str | None, status: str | None) -> str | None:
    """A run's label in GridData.runs: its style key (run_key), None while pending (queued
    or running), so that failed and cancelled runs are not drawn as runs to come."""
    key = run_key(regime, status)
    return None if key == PENDING else key


def axis_positions(values: np.ndarray, log: bool, v: np.ndarray) -> np.ndarray:
    """Fractional grid indices of the values v on an axis of the given values (NaN where
    a log axis cannot place them)."""
    v = np.asarray(v, dtype=float)
    if len(values) == 1:
        return np.zeros_like(v)
    if log:
        lo, hi = np.log(values[0]), np.log(values[-1])
        with np.errstate(divide="ignore", invalid="ignore"):
            v = np.where(v > 0, np.log(np.where(v > 0, v, 1.0)), np.nan)
    else:
        lo, hi = values[0], values[-1]
    return (v - lo) / (hi - lo) * (len(values) - 1)


def curve_blocks(data: GridData, curve: tuple[np.ndarray, np.ndarray] | None, sx: int,
                 sy: int, *, join: bool = True) -> set[tuple[int, int]]:
    """The blocks (col, row) of sx x sy points a curve passes through (the exact Hopf
    curve), interpolated so that steep stretches stay joined; with ``join`` False only
    the blocks of its points (the fold of cycles, one point per tau)."""
    if curve is None or len(curve[0]) == 0:
        return set()
    fx = axis_positions(data.xs, data.x_log, curve[0])
    fy = axis_positions(data.ys, data.y_log, curve[1])
    if join and len(fx) > 1:
        raw = np.maximum(np.maximum(np.abs(np.diff(fx)) / sx, np.abs(np.diff(fy)) / sy), 1) * 2
        steps = np.where(np.isfinite(raw), raw, 1).astype(int)  # a gap: its ends only
        seg = np.repeat(np.arange(len(fx) - 1), steps + 1)
        s = np.concatenate([np.linspace(0.0, 1.0, n + 1) for n in steps])
        fx = fx[seg] + s * (fx[seg + 1] - fx[seg])
        fy = fy[seg] + s * (fy[seg + 1] - fy[seg])
    inside = (np.isfinite(fx) & np.isfinite(fy) & (fx >= -0.5) & (fx <= len(data.xs) - 0.5)
              & (fy >= -0.5) & (fy <= len(data.ys) - 0.5))
    cols = np.round(fx[inside]).astype(int) // sx
    rows = np.round(fy[inside]).astype(int) // sy
    return set(zip(cols.tolist(), rows.tolist(), strict=True))
