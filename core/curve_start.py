"""A curve in two parameters as a restartable computation: what it asks (CurveSpec), its
walk point by point (start, then ``step``), the same walk rebuilt from the points already
computed (resume), and its codimension-two points once it has ended (``found``).

The curves: the fold of cycles (core.fold_continuation, started by core.fold_start; its
points carry the state a resumption predicts from: the unknowns, the border, the secant and
the next step), the period doubling and the torus bifurcation the same way
(core.flip_continuation, core.torus_continuation; a torus point's border holds its
kappa), and the Hopf curve with its first Lyapunov coefficient (core.lyapunov_coefficient:
the Hopf point in the first parameter at values of the second
``max_step`` apart; a resumption takes up the next value). A worker saves each point as it
comes (slopetui.queue.curve_jobs); one that takes over a curve whose worker died rebuilds it
from those and goes on as if never stopped.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from core.codim2 import Codim2, codim2_points
from core.flip_continuation import FlipCurve, start_at_flip
from core.floquet import Multipliers
from core.fold_continuation import CurvePoint, FoldCurve, step
from core.fold_start import start_at_fold
from core.lyapunov_coefficient import HopfCurvePoint, bautin, hopf_curve
from core.orbit import Grid
from core.params import Params
from core.torus_continuation import TorusCurve, start_at_torus

#: The curves: from a fold of cycles, the Hopf curve, from a period doubling, from a torus
#: bifurcation.
STARTS = ("fold", "hopf", "pd", "ns")
#: Each curve from a bifurcation of cycles: its class, how it starts (from the branch's
#: first such crossing up to the spec's branch_end), and its border's length in units of
#: the reduced state's size n, plus extra numbers (a fold's border has the period too, a
#: torus's two columns and kappa).
CROSSING_STARTS = {"pd": (FlipCurve, start_at_flip, 1, 0), "ns": (TorusCurve, start_at_torus, 2, 1)}
#: Newton's last resort along a fold curve: a step shorter than this ends it.
MIN_STEP = 1e-6


@dataclass(frozen=True)
class CurveSpec:
    """A curve in (``name``, ``second``) from ``params``: ``start`` "fold" (the fold of
    cycles of the branch in ``name`` from the first Hopf point) or "hopf" (the Hopf curve);
    grid step ``dt``; until ``second`` reaches ``to``; at most ``max_points`` points; steps
    of at most ``max_step`` (along the fold curve, or between Hopf points in ``second``);
    from the ``hopf_branch``-th Hopf point (the n-th root pair's crossing: its Hopf curve,
    or the fold of the branch born there)."""

    params: Params
    name: str
    second: str
    start: str
    dt: float
    to: float
    max_points: int
    max_step: float
    hopf_branch: int = 1
    #: "pd", "ns": where the one-parameter branch from the Hopf point is followed to, at
    #: most, looking for its first period doubling or torus bifurcation.
    branch_end: float | None = None


@dataclass(frozen=True)
class SavedCurvePoint:
    """A curve point as saved: both parameters and the period; a fold's amplitude,
    quadratic coefficient, multipliers, Newton steps, next step and resume state (float64:
    n_delay, dt0, direction, then y, the border c and the secant t, NaN before the first
    step); a Hopf point's l1 (the rest None)."""

    first: float
    second: float
    period: float
    amplitude: float | None = None
    l1: float | None = None
    curvature: float | None = None
    multipliers: Multipliers | None = None
    newton_steps: int | None = None
    step: float | None = None
    state: np.ndarray | None = None


def hopf_count(start: float, end: float, step: float) -> int:
    """The Hopf curve's points from start to end at most ``step`` apart, ends included (a
    span that is a whole number of steps up to rounding takes that number)."""
    return max(2, math.ceil(abs(end - start) / step - 1e-9) + 1)


def hopf_values(spec: CurveSpec) -> np.ndarray:
    """The second parameter's values of a Hopf curve (hopf_count of them)."""
    here = getattr(spec.params, spec.second)
    return np.linspace(here, spec.to, hopf_count(here, spec.to, spec.max_step))


class FoldWalk:
    """A fold curve walked point by point."""

    def __init__(self, spec: CurveSpec, curve: FoldCurve) -> None:
        self.spec, self.curve = spec, curve

    @property
    def end(self) -> str:
        return self.curve.end

    def step(self) -> SavedCurvePoint | None:
        point = step(self.curve, self.spec.to, self.spec.max_points, MIN_STEP)
        return None if point is None else self._saved(point)

    def _saved(self, point: CurvePoint) -> SavedCurvePoint:
        c = self.curve
        t = c.t if c.t is not None else np.full(c.y.size, np.nan)
        state = np.concatenate(([c.n_delay, c.dt0, c.direction], c.y, c.c, t))
        curvature = None if math.isnan(point.curvature) else point.curvature  # a torus's
        return SavedCurvePoint(point.first, point.second, point.period, point.amplitude,
                               None, curvature, point.multipliers, point.newton_steps,
                               c.h, state)

    def found(self) -> list[Codim2]:
        return codim2_points(self.curve)


class HopfWalk:
    """A Hopf curve, one value of the second parameter after another."""

    def __init__(self, spec: CurveSpec, points: list[HopfCurvePoint] | None = None) -> None:
        self.spec = spec
        self.values = hopf_values(spec)
        self.points = points or []
        self.end = ""

    def step(self) -> SavedCurvePoint | None:
        if self.end:
            return None
        if len(self.points) >= len(self.values):
            self.end = f"reached {self.spec.second} = {self.spec.to:g}"
            return None
        value = float(self.values[len(self.points)])
        point = next(hopf_curve(self.spec.params, (self.spec.name, self.spec.second), [value],
                                self.spec.dt, self.spec.hopf_branch))
        self.points.append(point)
        if len(self.points) == len(self.values):
            self.end = f"reached {self.spec.second} = {self.spec.to:g}"
        return SavedCurvePoint(point.first, point.second, point.period, l1=point.l1)

    def found(self) -> list[Codim2]:
        """The Bautin points: l1 = 0 between neighbours whose l1 differ in sign."""
        out = []
        names = (self.spec.name, self.spec.second)
        for a, b in itertools.pairwise(self.points):
            if a.l1 * b.l1 < 0:
                bp = bautin(self.spec.params, names, a, b, self.spec.dt, self.spec.hopf_branch)
                out.append(Codim2("bautin", bp.first, bp.second, bp.period,
                                  "l1 = 0 on the Hopf curve"))
        return out


Walk = FoldWalk | HopfWalk


def start(spec: CurveSpec) -> Walk:
    """The walk from its start: the fold found on the branch from the Hopf point (several
    seconds: a one-parameter continuation to its turn), or the Hopf curve's first value.
    Raises OrbitError where there is no fold to start from."""
    if spec.start == "hopf":
        return HopfWalk(spec)
    if spec.start in CROSSING_STARTS:
        if spec.branch_end is None:
            raise ValueError(f"a {spec.start} curve needs the branch's end (branch_end)")
        begin = CROSSING_STARTS[spec.start][1]
        return FoldWalk(spec, begin(spec.params, (spec.name, spec.second), spec.dt,
                                    spec.branch_end, spec.to, max_step=spec.max_step,
                                    hopf_branch=spec.hopf_branch))
    curve = start_at_fold(spec.params, (spec.name, spec.second), spec.to, spec.dt,
                          max_step=spec.max_step, hopf_branch=spec.hopf_branch)
    return FoldWalk(spec, curve)


def resume(spec: CurveSpec, saved: list[SavedCurvePoint]) -> Walk:
    """The walk rebuilt from its saved points, ready to take the next."""
    if spec.start == "hopf":
        return HopfWalk(spec, [HopfCurvePoint(s.first, s.second, s.period,
                                              float(s.l1 if s.l1 is not None else math.nan))
                               for s in saved])
    last = saved[-1]
    assert last.state is not None and last.step is not None
    n_delay, dt0, direction = int(last.state[0]), float(last.state[1]), float(last.state[2])
    n = Grid(1.0, n_delay).size
    y = last.state[3:3 + n + 3].copy()
    base = spec.params.with_(**{spec.name: float(y[-2]), spec.second: float(y[-1])})
    kind, _, columns, extra = CROSSING_STARTS.get(spec.start, (FoldCurve, None, 1, 1))
    border = columns * n + extra
    c = last.state[3 + n + 3:3 + n + 3 + border].copy()
    t = last.state[3 + n + 3 + border:].copy()
    curve = kind(base, (spec.name, spec.second), n_delay, dt0, y, c, y[:n].copy(),
                 np.zeros(n), last.step, spec.max_step,
                 t=None if np.isnan(t).any() else t, direction=direction)
    _, shot, _ = curve._F(y)
    curve.zdot_ref = shot.d_dT.copy()
    curve.points = [CurvePoint(s.first, s.second, s.period, float(s.amplitude or 0.0),
                               float(s.curvature if s.curvature is not None else math.nan),
                               _multipliers(s), int(s.newton_steps or 0),
                               _kappa(s, n, border) if kind is TorusCurve else math.nan,
                               None if s.state is None else s.state[3:3 + n + 3].copy())
                      for s in saved]
    return FoldWalk(spec, curve)


def _kappa(s: SavedCurvePoint, n: int, border: int) -> float:
    """A torus point's kappa: its border's last number."""
    return math.nan if s.state is None else float(s.state[3 + n + 3 + border - 1])


def _multipliers(s: SavedCurvePoint) -> Multipliers:
    assert s.multipliers is not None, "a fold point is saved with its multipliers"
    return s.multipliers


__all__ = ["STARTS", "CurveSpec", "FoldWalk", "HopfWalk", "SavedCurvePoint", "Walk",
           "hopf_count", "hopf_values", "resume", "start"]
