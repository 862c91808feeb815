"""Pseudo-arclength continuation of a periodic orbit in one parameter, with its folds,
period doublings and tori located on the way.

Unknowns y = (z, T, p): the reduced state on the section, the period and the parameter.
Each point solves P(z, T; p) = z, the phase condition against the previous point, and
<t, y - y_pred> = 0 (t the unit secant of the last two points, y_pred = y_prev + h t) by
Newton-Krylov on the bordered system (core.shooting's scaling; dP/dp by a central
difference, two shots). The step h grows after quick corrections and halves after slow or
failed ones. Every point gets its Floquet multipliers (core.floquet); between two points

    - the parameter's direction turns (t_p changes sign): a fold of cycles, located by
      the fold's minimally augmented system from the point before the turn (locate_fold,
      core.fold_continuation);
    - a real multiplier crosses |mu| = 1 near -1: a period doubling;
    - a complex pair crosses |mu| = 1: a torus (Neimark-Sacker);
    - a real multiplier crosses +1 while the parameter keeps its direction: a branch point,

the last three judged against the crossing multiplier's uncertainty and located on
corrected orbits (core.multiplier_crossing), or "undetermined" where the crossing lies
within that uncertainty. A branch whose amplitude vanishes has reached a Hopf point
(reported as "hopf").

A tau-continuation keeps N = tau / dt fixed and lets dt follow tau, so the state keeps its
size.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass

import numpy as np

from core.floquet import Multipliers, multipliers
from core.fold_continuation import FoldCurve
from core.hopf_start import HopfPoint, hopf_point, small_orbit
from core.multiplier_crossing import (
    WIDEN,
    Orbit,
    corrected,
    crossing_multiplier,
    judge,
    uncertainty,
)
from core.orbit import Grid, OrbitError, PeriodMap, Shot
from core.params import ParameterError, Params
from core.shooting import Solution, solve_krylov, weighted_dot

#: Newton steps that make a continuation step count as easy (the step grows by GROW) or
#: as hard (it shrinks by half; a failure does too).
EASY_STEPS, HARD_STEPS, GROW = 3, 7, 1.5
#: Newton's tolerance along a branch, and its step budget per point.
BRANCH_TOL, BRANCH_NEWTON = 1e-9, 10
#: The relative step of the central difference dP/dp.
FD_STEP = 1e-6
#: Multipliers computed per branch point (enough to follow the crossing ones).
BRANCH_MULTIPLIERS = 6


@dataclass(frozen=True)
class BranchPoint:
    """One orbit on a branch: parameter value, period, amplitude, multipliers."""

    value: float
    period: float
    amplitude: float
    multipliers: Multipliers
    z: np.ndarray
    tangent_p: float

    @property
    def stable(self) -> bool:
        return self.multipliers.stable


@dataclass(frozen=True)
class Bifurcation:
    """A bifurcation located on a branch: its type (fold, period-doubling, torus,
    branch-point, hopf, or undetermined: a crossing within the multipliers' error),
    parameter value, period there, the crossing multiplier, and for a multiplier's
    crossing the figures that decided it (``reason``)."""

    type: str
    value: float
    period: float
    multiplier: complex
    reason: str = ""


def params_at(p: Params, name: str, value: float) -> Params:
    return p.with_(**{name: value})


def grid_at(g: Grid, p: Params, name: str) -> Grid:
    """tau moves dt (N fixed); other parameters keep the grid."""
    return Grid(p.tau / g.n_delay, g.n_delay) if name == "tau" else g


class Branch:
    """A continuation in ``name`` from one corrected orbit."""

    def __init__(self, p: Params, g: Grid, name: str, y: np.ndarray, t: np.ndarray,
                 shot: Shot, step: float, max_step: float) -> None:
        self.base, self.g0, self.name = p, g, name
        self.h, self.max_step = step, max_step
        self.points: list[BranchPoint] = []
        self.states: list[tuple[np.ndarray, np.ndarray]] = []  # (y, t) of each point
        self.end = ""  # why the walk ended (walk sets it)
        self.y, self.shot = y, shot
        self.t = self._unit(t)

    @classmethod
    def from_orbit(cls, p: Params, g: Grid, name: str, sol: Solution, direction: float,
                   step: float, max_step: float) -> Branch:
        """From a corrected orbit, first along the parameter (direction +1 or -1)."""
        t = np.zeros(g.size + 2)
        t[-1] = direction
        return cls(p, g, name, np.concatenate((sol.z, [sol.period, getattr(p, name)])), t,
                   sol.shot, step, max_step)

    @classmethod
    def from_hopf(cls, p: Params, name: str, dt: float, eps: float, step: float,
                  max_step: float, hopf_branch: int = 1) -> tuple[Branch, HopfPoint]:
        """From the n-th Hopf point (n = hopf_branch) of the noisy steady state
        (core.hopf_start): the orbit of amplitude eps along the critical eigenvector,
        corrected with the parameter free, then onward in the direction of growing
        amplitude."""
        hopf = hopf_point(p, name, hopf_branch)
        q = params_at(p, name, hopf.value)
        g = Grid.of(q, dt)
        z0, dz = small_orbit(hopf, g, eps)
        y0 = np.concatenate((z0, [hopf.period, hopf.value]))
        t = np.concatenate((dz, [0.0, 0.0]))
        pm = PeriodMap(q, g)
        shot = pm.shoot(z0, hopf.period)
        branch = cls(q, g, name, y0, t, shot, step, max_step)
        y, shot, _ = branch._correct(y0, z0, shot.d_dT)
        branch.y, branch.shot = y, shot
        return branch, hopf

    def restarted(self, i: int, step: float) -> Branch:
        """A branch that starts again from point i, with steps of at most ``step``."""
        y, t = self.states[i]
        n = self.g0.size
        shot = self.map_at(float(y[-1])).shoot(y[:n], float(y[n]))
        return Branch(self.base, self.g0, self.name, y.copy(), t.copy(), shot, step, step)

    # -- norms --

    def _w(self) -> np.ndarray:
        return np.concatenate((self.g0.weights, [1.0, 1.0]))

    def _unit(self, v: np.ndarray) -> np.ndarray:
        return v / math.sqrt(weighted_dot(v, v, self._w()))

    def map_at(self, value: float) -> PeriodMap:
        p = params_at(self.base, self.name, value)
        return PeriodMap(p, grid_at(self.g0, p, self.name))

    # -- one corrected point --

    def _correct(self, y_pred: np.ndarray, z_ref: np.ndarray, zdot_ref: np.ndarray
                 ) -> tuple[np.ndarray, Shot, int]:
        w = self._w()
        sw = np.sqrt(w)
        n = self.g0.size
        y = y_pred.copy()
        for step in range(BRANCH_NEWTON + 1):
            pm = self.map_at(float(y[-1]))
            shot = pm.shoot(y[:n], float(y[n]))
            r = shot.value - y[:n]
            phase = weighted_dot(zdot_ref, y[:n] - z_ref, self.g0.weights)
            arc = weighted_dot(self.t, y - y_pred, w)
            res = math.sqrt(weighted_dot(r, r, self.g0.weights) + phase ** 2 + arc ** 2)
            if res < BRANCH_TOL:
                return y, shot, step
            if step == BRANCH_NEWTON:
                break
            hp = FD_STEP * max(1.0, abs(float(y[-1])))
            d_dp = (self.map_at(float(y[-1]) + hp).shoot(y[:n], float(y[n])).value
                    - self.map_at(float(y[-1]) - hp).shoot(y[:n], float(y[n])).value) / (2 * hp)

            def apply(x: np.ndarray, pm: PeriodMap = pm, shot: Shot = shot,
                      d_dp: np.ndarray = d_dp) -> np.ndarray:
                d = x / sw
                dz, dT, dp = d[:n], d[n], d[n + 1]
                top = pm.tangent(shot, dz) - dz + shot.d_dT * dT + d_dp * dp
                return np.concatenate((sw[:n] * top, [weighted_dot(zdot_ref, dz, self.g0.weights),
                                                      weighted_dot(self.t, d, w)]))

            x, _ = solve_krylov(apply, -np.concatenate((sw[:n] * r, [phase, arc])),
                                min(1e-6, 0.1 * res))
            y = y + x / sw
        raise OrbitError(f"no convergence at {self.name} = {float(y[-1]):.6g}")

    def _point(self, y: np.ndarray, shot: Shot, pm: PeriodMap) -> BranchPoint:
        n = self.g0.size
        m_y = shot.traj[1, self.g0.n_delay:shot.col + 1]
        return BranchPoint(float(y[-1]), float(y[n]), float(np.ptp(m_y)),
                           multipliers(pm, shot, BRANCH_MULTIPLIERS), y[:n].copy(),
                           float(self.t[-1]))

    # -- the walk --

    def first(self) -> BranchPoint:
        point = self._point(self.y, self.shot, self.map_at(float(self.y[-1])))
        self.points.append(point)
        self.states.append((self.y.copy(), self.t.copy()))
        return point

    def advance(self, min_step: float) -> BranchPoint:
        """One step along the branch (shrinking the step until Newton converges)."""
        n = self.g0.size
        z_ref, zdot_ref = self.y[:n], self.shot.d_dT
        while True:
            y_pred = self.y + self.h * self.t
            try:
                y, shot, steps = self._correct(y_pred, z_ref, zdot_ref)
                break
            except ParameterError as exc:
                self.h *= 0.5
                if self.h < min_step:
                    raise OrbitError(f"the branch leaves the physical range after {self.name} "
                                     f"= {float(self.y[-1]):.6g}: {exc}") from None
            except OrbitError:
                self.h *= 0.5
                if self.h < min_step:
                    raise OrbitError(f"the branch could not be continued past {self.name} = "
                                     f"{float(self.y[-1]):.6g} (step below {min_step:g})") from None
        self.t = self._unit(y - self.y)
        self.y, self.shot = y, shot
        if steps <= EASY_STEPS:
            self.h = min(self.h * GROW, self.max_step)
        elif steps >= HARD_STEPS:
            self.h *= 0.5
        point = self._point(y, shot, self.map_at(float(y[-1])))
        self.points.append(point)
        self.states.append((y.copy(), self.t.copy()))
        return point


def _fold_value(a: BranchPoint, b: BranchPoint, c: BranchPoint | None) -> tuple[float, float]:
    """Where the parameter turns: the vertex of the parabola p(A) through a, b, c (A the
    amplitude, monotone through a fold of cycles) when it lies between them; else the
    extreme point itself."""
    pts = [a, b] if c is None else [a, b, c]
    extreme = min(pts, key=lambda q: q.value) if b.value <= a.value else max(pts, key=lambda q: q.value)
    if c is not None:
        amps = [q.amplitude for q in pts]
        coef = np.polyfit(amps, [q.value for q in pts], 2)
        if coef[0] != 0.0:
            a_star = -coef[1] / (2 * coef[0])
            if min(amps) <= a_star <= max(amps):
                order = np.argsort(amps)
                period = float(np.interp(a_star, np.array(amps)[order],
                                         np.array([q.period for q in pts])[order]))
                return float(np.polyval(coef, a_star)), period
    return extreme.value, extreme.period


def _orbit(branch: Branch, i: int) -> Orbit:
    y, _ = branch.states[i]
    n = branch.g0.size
    value = float(y[-1])
    return Orbit(value, y[:n], float(y[n]), grid_at(branch.g0, params_at(branch.base, branch.name,
                                                                           value), branch.name),
                 branch.points[i].multipliers)


def judged_crossing(branch: Branch, i: int, turns: set[int]) -> Bifurcation | None:
    """A multiplier through the unit circle between points i - 1 and i, if any, judged
    against its uncertainty and located on corrected orbits (core.multiplier_crossing):
    a period doubling, torus or branch point where the crossing is real, "undetermined"
    (with the reason) where it lies within the multipliers' error. Each side may be
    judged up to WIDEN points farther, never across a fold (``turns``)."""
    last = len(branch.points) - 1
    before = [i - 1]
    while len(before) <= WIDEN and before[-1] > 0 and before[-1] not in turns:
        before.append(before[-1] - 1)
    after = [i]
    while len(after) <= WIDEN and after[-1] < last and after[-1] + 1 not in turns:
        after.append(after[-1] + 1)
    n = branch.g0.size
    values = [float(y[-1]) for y, _ in branch.states]

    def at(value: float, z: np.ndarray, period: float) -> Orbit:
        orbit = corrected(branch.map_at(value), z, period)
        return Orbit(value, orbit.z, orbit.period, orbit.grid, orbit.multipliers)

    def error(o: Orbit, mu: complex) -> float:
        return uncertainty(branch.map_at(o.value), o.z, o.period, o.multipliers, mu)

    def seed(value: float) -> tuple[np.ndarray, float]:
        """The branch's state interpolated between its two points around ``value``."""
        span = sorted(before + after)
        for j, k in itertools.pairwise(span):
            if (values[j] - value) * (values[k] - value) <= 0 and values[j] != values[k]:
                s = (value - values[j]) / (values[k] - values[j])
                y = branch.states[j][0] + s * (branch.states[k][0] - branch.states[j][0])
                return y[:n], float(y[n])
        y = branch.states[i][0]
        return y[:n], float(y[n])

    verdict = judge(at, [_orbit(branch, j) for j in before], [_orbit(branch, j) for j in after],
                    error, seed)
    if verdict is None:
        return None
    return Bifurcation(verdict.kind, verdict.value, verdict.period, verdict.multiplier,
                       verdict.reason)


#: The branch has reached the Hopf point when its amplitude (peak-to-peak m_y) falls below
#: this fraction of the largest amplitude seen on it: the orbit shrinks to the steady
#: state, where a continuation would turn back along the same orbits shifted by half a
#: period.
HOPF_FRACTION = 1e-3


def at_hopf(points: list[BranchPoint]) -> bool:
    return len(points) > 1 and points[-1].amplitude < HOPF_FRACTION * max(
        p.amplitude for p in points)


def step(branch: Branch, stop: Callable[[BranchPoint], bool], max_points: int,
         min_step: float) -> BranchPoint | None:
    """The branch's next point, or None once it has ended: at ``stop``'s word, at
    max_points, at the Hopf point, or at a point Newton cannot reach (the parameter's
    physical range ends there, or the orbit leaves the finite range). Why it ended is
    left in ``branch.end``; the point that ends it is still returned."""
    if branch.end:
        return None
    if not branch.points:
        return branch.first()
    if len(branch.points) >= max_points:
        branch.end = f"{max_points} points computed"
        return None
    try:
        point = branch.advance(min_step)
    except OrbitError as exc:
        branch.end = str(exc)
        return None
    check_end(branch, stop)
    return point


def check_end(branch: Branch, stop: Callable[[BranchPoint], bool]) -> None:
    """Set ``branch.end`` if its last point ends it: at the Hopf point, or at ``stop``'s
    word (a resumed branch asks again: its last point may have been its end)."""
    if len(branch.points) > 1 and at_hopf(branch.points):
        branch.end = "the amplitude vanished: the branch reached the Hopf point"
    elif len(branch.points) > 1 and stop(branch.points[-1]):
        branch.end = "reached the requested end"


def walk(branch: Branch, stop: Callable[[BranchPoint], bool], max_points: int,
         min_step: float) -> Iterator[BranchPoint]:
    """The branch point by point until it ends (see ``step``)."""
    while (point := step(branch, stop, max_points, min_step)) is not None:
        yield point


def criticality(points: list[BranchPoint]) -> str:
    """Of a branch started at the Hopf point: "subcritical" when its first orbits are
    unstable (they coexist with the stable steady state), "supercritical" when stable.

    Judged on the first orbit ten times the starting amplitude, or on the last orbit
    before the branch first turns if that comes sooner: past a fold the branch is another
    family. (Measured: (a, tau) plane, k = 12, tau = 5, steps of up to 3.7 in a: the
    fold lies 0.68 above the Hopf point, and the first orbit ten times the starting
    amplitude was already past it, stable, so the branch was called supercritical; with
    steps of 0.5 its orbits up to the fold are unstable: subcritical.)"""
    start = points[0].amplitude
    before_turn = points
    for i in range(1, len(points)):
        if points[i - 1].tangent_p * points[i].tangent_p < 0:
            before_turn = points[:i]
            break
    for point in before_turn[1:]:
        if point.amplitude > 10 * start:
            return "supercritical" if point.stable else "subcritical"
    return "supercritical" if before_turn[-1].stable else "subcritical"


#: Fold refinement: levels of re-walking through the turn, each with steps this many
#: times shorter. Measured against DDE-BIFTOOL's fold continuation (SetupPOfold,
#: collocation degree 4 on 60 and 120 intervals; benchmarks/ddebiftool): with two levels
#: `continue --from-hopf` put the fold at tau = 10 4.5e-6 off (1.2139058 against
#: 1.2139004) and core.fold_curve at tau = 20 1.5e-6 off; with three, every fold at
#: tau = 2, 5, 10, 20 lies within 5e-8 of DDE-BIFTOOL's, for ~20% more time.
FOLD_LEVELS, FOLD_SHRINK = 3, 20


def locate_fold(branch: Branch, i: int, min_step: float) -> tuple[float, float]:
    """The fold between points i - 1 and i of ``branch``: the point before the turn
    corrected onto the fold's minimally augmented system (core.fold_continuation: g = dp/ds
    = 0, a second parameter held), or, where that Newton fails or lands away from the turn,
    the turn re-walked with shorter steps.

    Measured at tau = 5.965229 (k): the re-walk's parabola put the fold at 1.9578449, at
    dt 0.01 and 0.006 alike; the augmented system at 1.9578557, and Newton at fixed k finds
    an orbit 2e-6 above it and none 2e-6 below it nor 2e-6 above the re-walk's value. At
    tau = 2, 10 and 20 both agree with DDE-BIFTOOL's folds to 3e-9 (benchmarks/ddebiftool)."""
    try:
        return _augmented_fold(branch, i)
    except (OrbitError, ParameterError, np.linalg.LinAlgError, ArithmeticError):
        return _rewalked_fold(branch, i, min_step)


def _augmented_fold(branch: Branch, i: int) -> tuple[float, float]:
    """The fold by core.fold_continuation from the state before the turn; OrbitError when
    it lands farther from the turn than the points around it reach."""
    y, t = branch.states[i - 1]
    n = branch.g0.size
    pm = branch.map_at(float(y[-1]))
    shot = pm.shoot(y[:n], float(y[n]))
    border = t[:n + 1] / math.sqrt(weighted_dot(t[:n + 1], t[:n + 1], branch._w()[:n + 1]))
    other = "k" if branch.name == "tau" else "tau"
    q = pm.p
    curve = FoldCurve(q, (branch.name, other), branch.g0.n_delay, pm.g.dt,
                      np.concatenate((y, [getattr(q, other)])), border, y[:n].copy(),
                      shot.d_dT.copy(), 0.0, 0.0)
    fold, _, _, _ = curve.correct(curve.y, None)
    values = [p.value for p in branch.points[max(i - 2, 0):i + 2]]
    reach = max(values) - min(values)
    value = float(fold[-2])
    if not min(values) - reach <= value <= max(values) + reach:
        raise OrbitError(f"the augmented fold at {value:.8g} lies away from the turn")
    return value, float(fold[n])


def _rewalked_fold(branch: Branch, i: int, min_step: float) -> tuple[float, float]:
    """The fold between points i - 1 and i, re-walked with shorter steps (FOLD_LEVELS)."""
    w = branch._w()
    y0, _ = branch.states[i - 1]
    y1, _ = branch.states[i]
    h = math.sqrt(weighted_dot(y1 - y0, y1 - y0, w))
    start = max(i - 2, 0)
    sub = branch
    for _ in range(FOLD_LEVELS):
        h /= FOLD_SHRINK
        sub = sub.restarted(start, h)
        sub.first()
        for _ in range(4 * FOLD_SHRINK):
            sub.advance(min_step)
            if sub.points[-2].tangent_p * sub.points[-1].tangent_p < 0:
                break
        else:
            break  # no turn within reach at this step: keep what the coarser level found
        start = max(len(sub.points) - 3, 0)
    pts = sub.points
    turn = next((j for j in range(1, len(pts)) if pts[j - 1].tangent_p * pts[j].tangent_p < 0),
                None)
    if turn is None:
        return _fold_value(branch.points[i - 1], branch.points[i],
                           branch.points[i + 1] if i + 1 < len(branch.points) else None)
    sub.advance(min_step)  # the point after the turn, for the parabola
    return _fold_value(pts[turn - 1], pts[turn], pts[turn + 1] if turn + 1 < len(pts) else None)


def _hopf_end(a: BranchPoint, b: BranchPoint) -> Bifurcation:
    """The Hopf point a branch ends at: near it p - p_H and T - T_H grow as the amplitude
    squared, so the last two points extrapolate to amplitude 0."""
    a2, b2 = a.amplitude ** 2, b.amplitude ** 2
    if a2 == b2:
        return Bifurcation("hopf", b.value, b.period, complex(1.0))
    value = (b.value * a2 - a.value * b2) / (a2 - b2)
    period = (b.period * a2 - a.period * b2) / (a2 - b2)
    return Bifurcation("hopf", value, period, complex(1.0))


def bifurcations(branch: Branch, min_step: float = 1e-9) -> list[Bifurcation]:
    """The bifurcations on a walked branch, in order.

    A fold is where the parameter turns (t_p changes sign), located by locate_fold. Its
    multiplier crosses +1 in the same or a neighbouring interval: that crossing is the
    fold's, not reported again. A branch ending at a vanishing amplitude ends at the Hopf
    point.
    """
    points = branch.points
    turns = {i for i in range(1, len(points))
             if points[i - 1].tangent_p * points[i].tangent_p < 0}
    found: list[tuple[int, Bifurcation]] = []
    for i in range(1, len(points)):
        a, b = points[i - 1], points[i]
        if i in turns:
            value, period = locate_fold(branch, i, min_step)
            found.append((i, Bifurcation("fold", value, period, complex(1.0))))
            continue
        moved = crossing_multiplier(a.multipliers, b.multipliers)
        if moved is None:
            continue
        if moved[1].real > 0 and (i - 1 in turns or i + 1 in turns):
            continue  # the fold's own multiplier, through +1 beside the turn
        if (bif := judged_crossing(branch, i, turns)) is not None:
            found.append((i, bif))
    if at_hopf(points):
        found.append((len(points), _hopf_end(points[-2], points[-1])))
    return [b for _, b in sorted(found, key=lambda ib: ib[0])]


__all__ = ["Bifurcation", "Branch", "BranchPoint", "bifurcations", "check_end", "criticality",
           "judged_crossing", "step", "walk"]
