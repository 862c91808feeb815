"""A sweep's runs as diagram data: grid positions, axis values, regimes and peaks.

An adaptive sweep's inferred runs come back like done ones (status done, their regime)
with ``inferred`` true; lattice points without a run yet (levels not queued yet) are
listed by ``SweepDiagram.unqueued`` so that drawings show them as pending.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from slopetui.store.database import Database
from slopetui.store.sweep_reads import diagram_rows
from slopetui.sweeps.control import UnknownSweep
from slopetui.sweeps.hopf_plane import Curve, hopf_boundary
from slopetui.sweeps.spec import SweepSpec, parse_spec


@dataclass(frozen=True)
class RunPoint:
    id: int
    ix: int
    iy: int
    x: float
    y: float | None
    status: str
    regime: str | None      # None unless done
    peaks: list[float]      # peak clusters of m_y; a sliding run gives its mean m_y
    error: str | None
    detail: str | None = None
    period_count: int | None = None
    lambda_max: float = float("nan")
    lambda_err: float = float("nan")
    drift: float = float("nan")  # window mean of m_y
    inferred: bool = False  # an adaptive sweep's regime taken from its cell's corners
    attractor: str | None = None  # fixed-point, fast-branch, periodic, torus, ... (done runs)
    flags: tuple[str, ...] = ()   # stiff-fallback, linear-transient, ... (core.classify)
    maxima_per_period: int | None = None
    settled: bool | None = None
    ic: int = 0  # which of the sweep's initial conditions (spec [[initial]])
    delta: float = float("nan")
    history: str = "constant"


@dataclass(frozen=True)
class SweepDiagram:
    id: int
    name: str
    spec: SweepSpec
    runs: list[RunPoint]

    @property
    def n_done(self) -> int:
        return sum(r.status == "done" for r in self.runs)

    @property
    def n_inferred(self) -> int:
        return sum(r.inferred for r in self.runs)

    @property
    def n_computed(self) -> int:
        """Done runs that were computed (or copied from a computed run), not inferred."""
        return sum(r.status == "done" and not r.inferred for r in self.runs)

    @property
    def n_points(self) -> int:
        """Runs the sweep will have: one per point of its lattice and initial condition
        (an adaptive sweep has runs for some so far)."""
        return self.spec.n_runs

    def unqueued(self) -> list[tuple[int, int, float, float | None]]:
        """(ix, iy, x, y) of the lattice points that have no run yet: an adaptive sweep's
        points of levels not queued yet, and those it will infer."""
        if len(self.runs) >= self.n_points:
            return []
        have = {(r.ix, r.iy) for r in self.runs}
        xs = self.spec.x.values()
        ys = self.spec.y.values() if self.spec.y else [None]
        return [(ix, iy, float(x), None if y is None else float(y))
                for iy, y in enumerate(ys) for ix, x in enumerate(xs) if (ix, iy) not in have]


def plane_hopf(spec: SweepSpec) -> Curve | None:
    """The exact Hopf curve over a 2-D sweep's plane, or None where the plane has none."""
    assert spec.y is not None
    x, y = spec.x, spec.y
    return hopf_boundary(spec.base, x.param, y.param,
                         (min(x.start, x.stop), max(x.start, x.stop)),
                         (min(y.start, y.stop), max(y.start, y.stop)))


def _read_spec(stored: dict[str, Any]) -> tuple[SweepSpec, str, str | None]:
    spec = parse_spec(stored)
    return spec, spec.x.param, spec.y.param if spec.y else None


def load_diagram(db: Database, sweep_id: int) -> SweepDiagram:
    """Everything a phase or bifurcation diagram of the sweep needs, in one read."""
    read = diagram_rows(db, sweep_id, _read_spec)
    if read is None:
        raise UnknownSweep(sweep_id)
    spec = read.spec
    runs = []
    for rid, ix, iy, x, y, status, regime, peaks, drift, error, detail, count, lam, lam_err, \
            inferred, attractor, flags, maxima, settled, ic, delta, history in read.rows:
        done = status == "done"
        # A sliding run has no peaks: it rests near the fixed point m_y = 0 (eqs. 14-17;
        # with noise d > 0 it drifts at a small constant m_y). It is drawn at its window
        # mean of m_y (the drift), the flat lower branch of Fig. 4A.
        shown = ([drift] if regime == "sliding" else list(peaks or [])) if done else []
        runs.append(RunPoint(rid, ix, iy, x, y if spec.y else None, status,
                             regime if done else None, shown, error, detail if done else None,
                             count if done else None, lam, lam_err, drift, bool(inferred),
                             attractor if done else None,
                             tuple(flags.split(",")) if done and flags else (),
                             maxima if done else None, settled if done else None, ic, delta,
                             history))
    return SweepDiagram(read.sweep_id, read.name, spec, runs)
