"""The fold of cycles continued as a curve in two parameters: a minimally augmented system.

At a fold of cycles the Jacobian of the orbit's equations in (z, T),

    F(z, T; p, q) = [ P(z, T) - z ; <zdot_ref, z - z_ref> ],     F_x = dF/d(z, T),

is singular (its null vector is the branch's tangent, which has no p-component there).
The scalar test function g is the last unknown of the bordered system

    [ F_x   F_p ] [v]   [0]
    [ c^T    0  ] [g] = [1]                                  (minimally augmented)

with c the null vector at the previous curve point and the border column F_p = dF/dp, which
is outside the range of F_x at a quadratic fold (its transversality condition): the matrix
is regular along the curve and g vanishes exactly at folds. (v, g) is the one-parameter
branch's tangent scaled to <c, v> = 1, so g = dp/ds: the fold is where the branch stops
moving in p, with no walk through the turn. The curve solves

    F(z, T; p, q) = 0,   g(z, T; p, q) = 0,   <t, Y - Y_pred> = 0

for Y = (z, T, p, q) (pseudo-arclength, t the secant of the last two points). Each Newton
step splits the linearised F-rows by block elimination into three solves with the bordered
matrix (matrix-free GMRES, core.shooting's scaling):

    Y + d0 + s1 phi1 + s2 phi2,   M d0 = [-F; 0],  M phi1 = [0; 1],  M phi2 = [-F_q; 0],

so every d0 + s1 phi1 + s2 phi2 solves the F-rows, and the two scalars come from the g-row
and the arclength row, with g's derivatives along d0, phi1, phi2 by forward differences
(the bordered system solved again at the displaced point). Only products with dP/dz are
needed, never its transpose. Newton converges quadratically up to those differences' error.

The border's p is the first parameter (the fold is a fold in p, the one-parameter branch's
parameter); q is the second. The delay grid keeps N = tau / dt points: when tau is one of
the two parameters dt follows it (core.continuation's tau-continuation), so the start
chooses N for the larger tau the curve will reach, and dt stays at most the one asked for.

Where the curve starts is core.fold_start's; the codimension-two points along it are
core.codim2's, from the points' quadratic coefficients and multipliers.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from core.floquet import Multipliers, multipliers
from core.orbit import Grid, OrbitError, PeriodMap, Shot
from core.params import ParameterError, Params
from core.shooting import solve_krylov, weighted_dot

#: Newton's tolerance on |F| (weighted) and on |g|, and its step budget per curve point.
#: The fold's parameter value is quadratic in g's error (g = dp/ds, and p(s) is extreme
#: there), so |g| < 1e-7 places the fold to ~1e-13 in p; measured, the folds at tau = 2, 5,
#: 10, 20 lie within 4e-9 of DDE-BIFTOOL's (benchmarks/ddebiftool), its collocation's own
#: accuracy.
CURVE_TOL, G_TOL, CURVE_NEWTON = 1e-9, 1e-7, 8
#: GMRES's relative tolerance for the bordered solves: g's forward differences divide its
#: error by FD_REL (1e-11 / 1e-6: ~1e-5 relative in g's derivatives).
BORDER_RTOL = 1e-11
#: The forward-difference step for g's derivatives and the central one for dF/dp, relative.
FD_REL = 1e-6
#: Steps along the curve: grow by GROW after at most EASY Newton steps, halve after a
#: failure or after HARD ones.
EASY, HARD, GROW = 2, 5, 1.5
#: The curve stops at the Hopf curve: the orbit's amplitude (peak-to-peak m_y) below this
#: fraction of the largest seen on the curve. Measured on the first three fold curves in
#: (k, tau): their ends, extrapolated to zero amplitude from there, lie within 3e-6 (k and
#: tau, relative) of the Bautin points where l1 = 0 (core.lyapunov_coefficient), and the
#: first within 3e-6 of DDE-BIFTOOL's; below it Newton needs 6-7 steps a point.
BAUTIN_FRACTION = 0.02
#: Multipliers per curve point: the two at +1 a fold has, and four to see crossings by.
CURVE_MULTIPLIERS = 6


@dataclass(frozen=True)
class CurvePoint:
    """One fold of cycles on the curve: both parameters, the period, the amplitude
    (peak-to-peak m_y), the quadratic coefficient (its sign says which way the branch
    turns), the multipliers, and how many Newton steps it took."""

    first: float
    second: float
    period: float
    amplitude: float
    curvature: float
    multipliers: Multipliers
    newton_steps: int
    #: A torus point's kappa = cos(arg mu) of its pair on the circle (NaN on other curves).
    kappa: float = math.nan
    #: The unknowns (z, T, p, q): where a multiplier's uncertainty is measured from
    #: (core.codim2).
    y: np.ndarray | None = field(default=None, compare=False, repr=False)


@dataclass
class LinearParts:
    """The bordered solves at one point (see the module doc)."""

    F: np.ndarray
    g: float
    d0: np.ndarray
    phi1: np.ndarray
    phi2: np.ndarray | None
    shot: Shot
    #: The test function's bordered solution (v, g): where its next solve starts.
    null: np.ndarray


@dataclass
class FoldCurve:
    """The fold of cycles in ``names[0]`` continued in ``names[1]`` (see the module doc).
    A subclass with its own test function and border continues another bifurcation of
    cycles the same way (core.flip_continuation)."""

    #: What the curve is a curve of, for messages.
    what: ClassVar[str] = "fold"
    #: Newton steps within which a point counts as easy (the next step grows: EASY).
    easy: ClassVar[int] = EASY

    base: Params
    names: tuple[str, str]
    n_delay: int
    dt0: float
    y: np.ndarray                      # (z, T, p, q)
    c: np.ndarray                      # the border: the null vector at the last point
    z_ref: np.ndarray
    zdot_ref: np.ndarray
    h: float
    max_step: float
    points: list[CurvePoint] = field(default_factory=list)
    t: np.ndarray | None = None        # the curve's unit tangent
    end: str = ""
    direction: float = 1.0             # +1: the curve starts towards growing q

    # -- the map at Y --

    def params(self, y: np.ndarray) -> Params:
        return self.base.with_(**{self.names[0]: float(y[-2]), self.names[1]: float(y[-1])})

    def grid(self, p: Params) -> Grid:
        return Grid(p.tau / self.n_delay, self.n_delay) if "tau" in self.names else \
            Grid(self.dt0, self.n_delay)

    def map_at(self, y: np.ndarray) -> PeriodMap:
        p = self.params(y)
        return PeriodMap(p, self.grid(p))

    @property
    def size(self) -> int:
        return 2 * self.n_delay + 4

    def weights(self) -> np.ndarray:
        """(z, T, p, q): the orbit's weights, 1 for the period and both parameters."""
        return np.concatenate((Grid(1.0, self.n_delay).weights, [1.0, 1.0, 1.0]))

    # -- F, dF/dp, g --

    def _F(self, y: np.ndarray) -> tuple[np.ndarray, Shot, PeriodMap]:
        n = self.size
        pm = self.map_at(y)
        shot = pm.shoot(y[:n], float(y[n]))
        phase = weighted_dot(self.zdot_ref, y[:n] - self.z_ref, pm.g.weights)
        return np.concatenate((shot.value - y[:n], [phase])), shot, pm

    def _dF(self, y: np.ndarray, i: int) -> np.ndarray:
        """dF/d(parameter i) by a central difference (the phase row does not depend on it)."""
        n = self.size
        hp = FD_REL * max(1.0, abs(float(y[i])))
        out = []
        for sign in (1.0, -1.0):
            ys = y.copy()
            ys[i] += sign * hp
            out.append(self.map_at(ys).shoot(y[:n], float(y[n])).value)
        return np.concatenate(((out[0] - out[1]) / (2 * hp), [0.0]))

    def _bordered(self, pm: PeriodMap, shot: Shot, f_p: np.ndarray, rhs: np.ndarray,
                  x0: np.ndarray | None = None) -> np.ndarray:
        """Solve M x = rhs (x = (dz, dT, dp)) by GMRES in sqrt(W)-scaled variables."""
        n = self.size
        w = np.concatenate((pm.g.weights, [1.0, 1.0]))
        sw = np.sqrt(w)
        wx = w[:n + 1]

        def apply(x: np.ndarray) -> np.ndarray:
            d = x / sw
            dz, dT, dp = d[:n], d[n], d[n + 1]
            top = pm.tangent(shot, dz) - dz + shot.d_dT * dT + f_p[:n] * dp
            return np.concatenate((sw[:n] * top,
                                   [weighted_dot(self.zdot_ref, dz, pm.g.weights),
                                    weighted_dot(self.c, d[:n + 1], wx)]))

        scaled = np.concatenate((sw[:n] * rhs[:n], rhs[n:]))
        guess = None if x0 is None else x0 * sw
        x, _ = solve_krylov(apply, scaled, BORDER_RTOL, x0=guess)
        return x / sw

    def _g(self, y: np.ndarray, x0: np.ndarray | None = None) -> tuple[float, np.ndarray]:
        """g at y (and the null vector (v, g)), from the bordered system at y."""
        _, shot, pm = self._F(y)
        f_p = self._dF(y, self.size + 1)
        rhs = np.zeros(self.size + 2)
        rhs[-1] = 1.0
        x = self._bordered(pm, shot, f_p, rhs, x0)
        return float(x[-1]), x

    def _linear(self, y: np.ndarray, free_q: bool) -> LinearParts:
        n = self.size
        F, shot, pm = self._F(y)
        f_p = self._dF(y, n + 1)
        zeros = np.zeros(n + 2)
        d0 = self._bordered(pm, shot, f_p, np.concatenate((-F, [0.0])))
        unit = zeros.copy()
        unit[-1] = 1.0
        v = self._bordered(pm, shot, f_p, unit)
        phi1 = np.concatenate((v, [0.0]))
        phi2 = None
        if free_q:
            f_q = self._dF(y, n + 2)
            u = self._bordered(pm, shot, f_p, np.concatenate((-f_q, [0.0])))
            phi2 = np.concatenate((u, [1.0]))
        return LinearParts(F, float(v[-1]), np.concatenate((d0, [0.0])), phi1, phi2, shot, v)

    def _dg(self, y: np.ndarray, g: float, d: np.ndarray, x0: np.ndarray) -> float:
        """g's derivative along d, by a forward difference."""
        size = math.sqrt(weighted_dot(d, d, self.weights()))
        if size == 0.0:
            return 0.0
        eps = FD_REL * max(1.0, math.sqrt(weighted_dot(y, y, self.weights()))) / size
        g_eps, _ = self._g(y + eps * d, x0)
        return (g_eps - g) / eps

    # -- one corrected point --

    def correct(self, y_pred: np.ndarray, t: np.ndarray | None
                ) -> tuple[np.ndarray, int, float, LinearParts]:
        """Newton on (F, g) from y_pred: with the arclength row along t, or with q fixed
        (t None). Returns the point, the steps taken, Dg.phi1 there and the bordered solves
        there (its shot and test function's solution, which accepting it reuses)."""
        y = y_pred.copy()
        w = self.weights()
        curvature = math.nan
        for step in range(CURVE_NEWTON + 1):
            lin = self._linear(y, t is not None)
            arc = 0.0 if t is None else weighted_dot(t, y - y_pred, w)
            res = math.sqrt(weighted_dot(lin.F, lin.F, np.concatenate(
                (Grid(1.0, self.n_delay).weights, [1.0]))) + arc * arc)
            x0 = lin.null
            dg1 = self._dg(y, lin.g, lin.phi1, x0)
            curvature = dg1
            if res < CURVE_TOL and abs(lin.g) < G_TOL:
                return y, step, curvature, lin
            if step == CURVE_NEWTON:
                break
            dg0 = self._dg(y, lin.g, lin.d0, x0)
            if lin.phi2 is None or t is None:
                s1 = -(lin.g + dg0) / dg1
                y = y + lin.d0 + s1 * lin.phi1
            else:
                dg2 = self._dg(y, lin.g, lin.phi2, x0)
                a = np.array([[dg1, dg2],
                              [weighted_dot(t, lin.phi1, w), weighted_dot(t, lin.phi2, w)]])
                b = -np.array([lin.g + dg0, arc + weighted_dot(t, lin.d0, w)])
                s1, s2 = np.linalg.solve(a, b)
                y = y + lin.d0 + s1 * lin.phi1 + s2 * lin.phi2
            if y[self.size] <= 0:
                raise OrbitError("the period left the positive range")
        raise OrbitError(f"the {self.what} curve's Newton did not converge at {self.names[0]} = "
                         f"{float(y[-2]):.6g}, {self.names[1]} = {float(y[-1]):.6g}")

    def _accept(self, y: np.ndarray, steps: int, curvature: float,
                lin: LinearParts) -> CurvePoint:
        """Take the corrected point y (``lin``: correct's solves there): the next border
        from its test function's solution, the phase reference, its multipliers."""
        n = self.size
        shot, pm = lin.shot, self.map_at(y)
        self.c = self._border(lin.null, pm)
        self.z_ref, self.zdot_ref = y[:n].copy(), shot.d_dT.copy()
        m_y = shot.traj[1, self.n_delay:shot.col + 1]
        point = CurvePoint(float(y[-2]), float(y[-1]), float(y[n]), float(np.ptp(m_y)),
                           curvature, multipliers(pm, shot, CURVE_MULTIPLIERS), steps,
                           y=y.copy())
        self.y = y
        self.points.append(point)
        return point

    def _border(self, null: np.ndarray, pm: PeriodMap) -> np.ndarray:
        """The next border: the null vector (v of the bordered solution), unit."""
        v = null[:self.size + 1]
        return v / math.sqrt(weighted_dot(v, v, np.concatenate((pm.g.weights, [1.0]))))

    def ended(self, point: CurvePoint) -> str:
        """Why the curve ends at its new ``point`` ("" if it goes on): a fold curve where
        the amplitude vanishes (the Hopf curve: a Bautin point)."""
        if point.amplitude < BAUTIN_FRACTION * max(q.amplitude for q in self.points):
            return "the amplitude vanished: the fold curve reached the Hopf curve"
        return ""

    def first(self) -> CurvePoint:
        """The fold at the start's q: Newton from the start with q fixed."""
        return self._accept(*self.correct(self.y, None))

    def advance(self, min_step: float) -> CurvePoint:
        """The next point along the curve (shrinking the step until Newton converges)."""
        if self.t is None:
            self.t = self._first_tangent()
        while True:
            y_pred = self.y + self.h * self.t
            try:
                y, steps, curvature, lin = self.correct(y_pred, self.t)
                break
            except (OrbitError, ParameterError, np.linalg.LinAlgError) as exc:
                self.h *= 0.5
                if self.h < min_step:
                    raise OrbitError(f"the {self.what} curve could not be continued past "
                                     f"{self.names[0]} = {float(self.y[-2]):.6g}, "
                                     f"{self.names[1]} = {float(self.y[-1]):.6g}: {exc}") from None
        step = y - self.y
        self.t = step / math.sqrt(weighted_dot(step, step, self.weights()))
        if steps <= self.easy:
            self.h = min(self.h * GROW, self.max_step)
        elif steps >= HARD:
            self.h *= 0.5
        return self._accept(y, steps, curvature, lin)

    def _first_tangent(self) -> np.ndarray:
        """The curve's direction at the first point: the null vector of (F, g)'s Jacobian,
        d = s1 phi1 + s2 phi2 with Dg.d = 0, oriented by ``direction``."""
        lin = self._linear(self.y, True)
        assert lin.phi2 is not None
        x0 = lin.null
        dg1 = self._dg(self.y, lin.g, lin.phi1, x0)
        dg2 = self._dg(self.y, lin.g, lin.phi2, x0)
        t = -dg2 * lin.phi1 + dg1 * lin.phi2
        t /= math.sqrt(weighted_dot(t, t, self.weights()))
        return t if t[-1] * self.direction > 0 else -t


def step(curve: FoldCurve, to: float, max_points: int, min_step: float = 1e-6
         ) -> CurvePoint | None:
    """The curve's next point, or None once it has ended: the first fold, then one point
    after another until names[1] passes ``to`` (that point is corrected at ``to``
    exactly), the amplitude vanishes (the Hopf curve: a Bautin point), max_points, or a
    point Newton cannot reach; why it ended is left in ``curve.end``."""
    if curve.end:
        return None
    if not curve.points:
        return curve.first()
    if len(curve.points) >= max_points:
        curve.end = f"{max_points} points computed"
        return None
    try:
        point = curve.advance(min_step)
    except OrbitError as exc:
        curve.end = str(exc)
        return None
    if (point.second - to) * curve.direction >= 0:
        try:
            fixed = _fixed_at(curve, to)
        except (OrbitError, ParameterError, np.linalg.LinAlgError) as exc:
            # the chord back to ``to`` can be too far from a curve that bends within the
            # last step: the point past ``to`` stays the last (seen only when the walk went
            # the wrong way, from tau = 10.03 back to 5, before curves were given their
            # direction; a safety net, not a case measured since)
            curve.end = (f"passed {curve.names[1]} = {to:g} (the last point at "
                         f"{point.second:.6g}; the point at {to:g} itself: {exc})")
            return point
        curve.points.pop()
        point = curve._accept(*fixed)
        curve.end = f"reached {curve.names[1]} = {to:g}"
    else:
        curve.end = curve.ended(point)
    return point


def walk(curve: FoldCurve, to: float, max_points: int, min_step: float = 1e-6
         ) -> Iterator[CurvePoint]:
    """The curve point by point until it ends (see ``step``)."""
    while (point := step(curve, to, max_points, min_step)) is not None:
        yield point


def _fixed_at(curve: FoldCurve, to: float) -> tuple[np.ndarray, int, float, LinearParts]:
    """The fold at names[1] = to exactly, from the last step's chord back to ``to``."""
    y = curve.y.copy()
    if curve.t is not None and curve.t[-1] != 0.0:
        y = y + curve.t * (to - y[-1]) / curve.t[-1]
    y[-1] = to
    return curve.correct(y, None)


__all__ = ["CurvePoint", "FoldCurve", "step", "walk"]
