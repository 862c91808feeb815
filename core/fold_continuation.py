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

Along the curve, tested between consecutive points:
    - cusp: the fold's quadratic coefficient Dg.phi1 (k''(s)) changes sign;
    - bautin (generalised Hopf): the amplitude vanishes: the fold meets the Hopf curve
      where its first Lyapunov coefficient changes sign (core.lyapunov_coefficient locates
      it there, on the Hopf curve);
    - fold-flip: a nontrivial multiplier crosses the unit circle near -1;
    - fold-ns: a complex pair crosses it (a torus curve ends there);
    - resonance-1:1: a third multiplier reaches +1.
Multiplier crossings count only when the multiplier moves through the circle by more than
UNIT_MARGIN (the accuracy of multipliers near the circle).
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterator
from dataclasses import dataclass, field

import numpy as np

from core.continuation import Branch
from core.floquet import Multipliers, multipliers
from core.orbit import Grid, OrbitError, PeriodMap, Shot
from core.params import ParameterError, Params
from core.shooting import solve_krylov, weighted_dot

#: Newton's tolerance on |F| (weighted) and on |g|, and its step budget per curve point.
#: The fold's parameter value is quadratic in g's error (g = dp/ds, and p(s) is extreme
#: there), so |g| < 1e-7 places the fold to ~1e-13 in p.
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
#: fraction of the largest seen on the curve.
BAUTIN_FRACTION = 0.02
#: Multipliers per curve point, and the margin a crossing must clear on both sides: at a
#: fold two multipliers sit at +1 (the flow's and the fold's); round-off moves
#: multipliers that sit on the circle by ~1e-7 (core.floquet.FLOW_TOL's measurements).
CURVE_MULTIPLIERS, UNIT_MARGIN = 6, 1e-5


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


@dataclass(frozen=True)
class Codim2:
    """A codimension-two point on the curve: its type and both parameters."""

    type: str
    first: float
    second: float
    period: float
    note: str = ""


@dataclass
class _Linear:
    """The bordered solves at one point (see the module doc)."""

    F: np.ndarray
    g: float
    d0: np.ndarray
    phi1: np.ndarray
    phi2: np.ndarray | None
    shot: Shot


@dataclass
class FoldCurve:
    """The fold of cycles in ``names[0]`` continued in ``names[1]`` (see the module doc)."""

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

    def _linear(self, y: np.ndarray, free_q: bool) -> _Linear:
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
        return _Linear(F, float(v[-1]), np.concatenate((d0, [0.0])), phi1, phi2, shot)

    def _dg(self, y: np.ndarray, g: float, d: np.ndarray, x0: np.ndarray) -> float:
        """g's derivative along d, by a forward difference."""
        size = math.sqrt(weighted_dot(d, d, self.weights()))
        if size == 0.0:
            return 0.0
        eps = FD_REL * max(1.0, math.sqrt(weighted_dot(y, y, self.weights()))) / size
        g_eps, _ = self._g(y + eps * d, x0)
        return (g_eps - g) / eps

    # -- one corrected point --

    def correct(self, y_pred: np.ndarray, t: np.ndarray | None) -> tuple[np.ndarray, int, float]:
        """Newton on (F, g) from y_pred: with the arclength row along t, or with q fixed
        (t None). Returns the point, the steps taken and Dg.phi1 there."""
        y = y_pred.copy()
        w = self.weights()
        curvature = math.nan
        for step in range(CURVE_NEWTON + 1):
            lin = self._linear(y, t is not None)
            arc = 0.0 if t is None else weighted_dot(t, y - y_pred, w)
            res = math.sqrt(weighted_dot(lin.F, lin.F, np.concatenate(
                (Grid(1.0, self.n_delay).weights, [1.0]))) + arc * arc)
            x0 = lin.phi1[:-1]
            dg1 = self._dg(y, lin.g, lin.phi1, x0)
            curvature = dg1
            if res < CURVE_TOL and abs(lin.g) < G_TOL:
                return y, step, curvature
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
        raise OrbitError(f"the fold curve's Newton did not converge at {self.names[0]} = "
                         f"{float(y[-2]):.6g}, {self.names[1]} = {float(y[-1]):.6g}")

    def _accept(self, y: np.ndarray, steps: int, curvature: float) -> CurvePoint:
        n = self.size
        _, shot, pm = self._F(y)
        _, null = self._g(y)
        v = null[:n + 1]
        self.c = v / math.sqrt(weighted_dot(v, v, np.concatenate((pm.g.weights, [1.0]))))
        self.z_ref, self.zdot_ref = y[:n].copy(), shot.d_dT.copy()
        m_y = shot.traj[1, self.n_delay:shot.col + 1]
        point = CurvePoint(float(y[-2]), float(y[-1]), float(y[n]), float(np.ptp(m_y)),
                           curvature, multipliers(pm, shot, CURVE_MULTIPLIERS), steps)
        self.y = y
        self.points.append(point)
        return point

    def first(self) -> CurvePoint:
        """The fold at the start's q: Newton from the start with q fixed."""
        y, steps, curvature = self.correct(self.y, None)
        return self._accept(y, steps, curvature)

    def advance(self, min_step: float) -> CurvePoint:
        """The next point along the curve (shrinking the step until Newton converges)."""
        if self.t is None:
            self.t = self._first_tangent()
        while True:
            y_pred = self.y + self.h * self.t
            try:
                y, steps, curvature = self.correct(y_pred, self.t)
                break
            except (OrbitError, ParameterError, np.linalg.LinAlgError) as exc:
                self.h *= 0.5
                if self.h < min_step:
                    raise OrbitError(f"the fold curve could not be continued past "
                                     f"{self.names[0]} = {float(self.y[-2]):.6g}, "
                                     f"{self.names[1]} = {float(self.y[-1]):.6g}: {exc}") from None
        step = y - self.y
        self.t = step / math.sqrt(weighted_dot(step, step, self.weights()))
        if steps <= EASY:
            self.h = min(self.h * GROW, self.max_step)
        elif steps >= HARD:
            self.h *= 0.5
        return self._accept(y, steps, curvature)

    def _first_tangent(self) -> np.ndarray:
        """The curve's direction at the first point: the null vector of (F, g)'s Jacobian,
        d = s1 phi1 + s2 phi2 with Dg.d = 0, oriented by ``direction``."""
        lin = self._linear(self.y, True)
        assert lin.phi2 is not None
        x0 = lin.phi1[:-1]
        dg1 = self._dg(self.y, lin.g, lin.phi1, x0)
        dg2 = self._dg(self.y, lin.g, lin.phi2, x0)
        t = -dg2 * lin.phi1 + dg1 * lin.phi2
        t /= math.sqrt(weighted_dot(t, t, self.weights()))
        return t if t[-1] * self.direction > 0 else -t


#: The parameters with a Hopf point to start a branch from (core.hopf_start).
HOPF_STARTS = ("k", "tau", "a", "b", "c")


def start_at_fold(p: Params, names: tuple[str, str], reach: float, dt: float = 0.01,
                  step: float = 0.05, max_step: float = 0.5, hopf_branch: int = 1,
                  n_delay: int | None = None) -> FoldCurve:
    """The curve's start: the one-parameter branch in names[0] from the Hopf point at p,
    walked to its first turn (core.continuation), the point before the turn corrected onto
    the fold with names[1] fixed. ``reach`` is the other end of names[1]'s range (the grid
    is chosen for the larger tau of the two). A fold in a parameter with no Hopf start
    (d, v) is reached along the fold surface instead: see ``_via_k``."""
    from core.fold_curve import step_sizes  # the one-parameter branch's own steps

    name, second = names
    if n_delay is None:
        n_delay = Grid.of(p, dt).n_delay
        if second == "tau":
            n_delay = math.ceil(max(p.tau, reach) / dt - 1e-9)
    if name not in HOPF_STARTS:
        return _via_k(p, names, reach, dt, step, max_step, n_delay)
    dt_start = p.tau / n_delay
    first, largest = step_sizes(p, name)
    branch, _ = Branch.from_hopf(p, name, dt_start, 1e-3, first, largest, hopf_branch)
    n_delay = branch.g0.n_delay
    branch.first()
    for _ in range(400):
        branch.advance(1e-9)
        pts = branch.points
        if pts[-2].tangent_p * pts[-1].tangent_p < 0:
            break
    else:
        raise OrbitError(f"the branch in {name} from the Hopf point has no fold within "
                         "400 points")
    y_b, t_b = branch.states[-2]
    n = branch.g0.size
    q = branch.map_at(float(y_b[-1])).p
    g = branch.g0 if name != "tau" else Grid(q.tau / n_delay, n_delay)
    pm = PeriodMap(q, g)
    shot = pm.shoot(y_b[:n], float(y_b[n]))
    c = t_b[:n + 1] / math.sqrt(weighted_dot(t_b[:n + 1], t_b[:n + 1],
                                             np.concatenate((g.weights, [1.0]))))
    y0 = np.concatenate((y_b, [getattr(p, second)]))
    return FoldCurve(p.with_(**{name: float(y_b[-1])}), names, n_delay, g.dt, y0, c,
                     y_b[:n].copy(), shot.d_dT.copy(), step, max_step,
                     direction=1.0 if reach > getattr(p, second) else -1.0)


def crossings(a: CurvePoint, b: CurvePoint) -> list[Codim2]:
    """Codimension-two points between two consecutive curve points (see the module doc)."""
    found: list[Codim2] = []
    if a.curvature * b.curvature < 0:
        s = a.curvature / (a.curvature - b.curvature)
        found.append(_between("cusp", a, b, s, "the fold's quadratic coefficient vanishes"))
    ma, mb = fold_others(a.multipliers), fold_others(b.multipliers)
    for mu_b in mb:
        if abs(abs(mu_b) - 1.0) < UNIT_MARGIN:
            continue
        mu_a = ma[int(np.argmin(np.abs(ma - mu_b)))] if ma.size else None
        if mu_a is None or abs(abs(mu_a) - 1.0) < UNIT_MARGIN:
            continue
        if (abs(mu_a) - 1.0) * (abs(mu_b) - 1.0) >= 0:
            continue
        s = (abs(mu_a) - 1.0) / ((abs(mu_a) - 1.0) - (abs(mu_b) - 1.0))
        if abs(mu_b.imag) > 1e-4:
            kind = "fold-ns"
        elif mu_b.real < 0:
            kind = "fold-flip"
        else:
            kind = "resonance-1:1"
        found.append(_between(kind, a, b, s, f"multiplier {mu_a:.6g} -> {mu_b:.6g}"))
    return found


def fold_others(m: Multipliers) -> np.ndarray:
    """The multipliers but the two at +1 a fold of cycles has (the flow's and the fold's)."""
    values = m.nontrivial
    if values.size:
        values = np.delete(values, int(np.argmin(np.abs(values - 1.0))))
    return values


def _between(kind: str, a: CurvePoint, b: CurvePoint, s: float, note: str) -> Codim2:
    return Codim2(kind, a.first + s * (b.first - a.first), a.second + s * (b.second - a.second),
                  a.period + s * (b.period - a.period), note)


def walk(curve: FoldCurve, to: float, max_points: int, min_step: float = 1e-6
         ) -> Iterator[CurvePoint]:
    """The curve point by point, from its first fold until names[1] passes ``to`` (the
    last point is then corrected at ``to`` exactly), the amplitude vanishes (the Hopf
    curve: a Bautin point), or max_points; why it ended is left in ``curve.end``."""
    yield curve.first()
    while len(curve.points) < max_points:
        try:
            point = curve.advance(min_step)
        except OrbitError as exc:
            curve.end = str(exc)
            return
        if (point.second - to) * curve.direction >= 0:
            curve.points.pop()
            yield curve._accept(*_fixed_at(curve, to))
            curve.end = f"reached {curve.names[1]} = {to:g}"
            return
        yield point
        if point.amplitude < BAUTIN_FRACTION * max(q.amplitude for q in curve.points):
            curve.end = "the amplitude vanished: the fold curve reached the Hopf curve"
            return
    curve.end = f"{max_points} points computed"


def _fixed_at(curve: FoldCurve, to: float) -> tuple[np.ndarray, int, float]:
    """The fold at names[1] = to exactly, from the last step's chord back to ``to``."""
    y = curve.y.copy()
    if curve.t is not None and curve.t[-1] != 0.0:
        y = y + curve.t * (to - y[-1]) / curve.t[-1]
    y[-1] = to
    return curve.correct(y, None)


def codim2_points(curve: FoldCurve) -> list[Codim2]:
    """The codimension-two points along a walked curve, in order."""
    found: list[Codim2] = []
    pts = curve.points
    for a, b in itertools.pairwise(pts):
        found.extend(crossings(a, b))
    if curve.end.startswith("the amplitude vanished"):
        a, b = pts[-2], pts[-1]
        a2, b2 = a.amplitude ** 2, b.amplitude ** 2
        s = a2 / (a2 - b2) if a2 != b2 else 1.0  # p and q are linear in amplitude^2 there
        found.append(_between("bautin", a, b, s, "the fold curve's end on the Hopf curve, "
                                                 "extrapolated to zero amplitude"))
    return found


__all__ = ["Codim2", "CurvePoint", "FoldCurve", "codim2_points", "crossings", "fold_others",
           "start_at_fold", "walk"]


def switched(curve: FoldCurve, names: tuple[str, str], towards: float, step: float = 0.05,
             max_step: float = 0.5) -> FoldCurve:
    """The same fold of cycles, continued from its last point in another pair of
    parameters: the bordered system takes names[0]'s column (any parameter whose column is
    outside F_x's range will do), and the curve starts towards names[1] = ``towards``."""
    p = curve.params(curve.y)
    n = curve.size
    y = np.concatenate((curve.y[:n + 1], [getattr(p, names[0]), getattr(p, names[1])]))
    return FoldCurve(p, names, curve.n_delay, curve.grid(p).dt, y, curve.c.copy(),
                     curve.z_ref.copy(), curve.zdot_ref.copy(), step, max_step,
                     direction=1.0 if towards > getattr(p, names[1]) else -1.0)


def _via_k(p: Params, names: tuple[str, str], reach: float, dt: float, step: float,
           max_step: float, n_delay: int) -> FoldCurve:
    """The fold in names[0] (d or v: no Hopf start) at p: the fold in k at p's other
    values, continued in (names[0], k) at p's tau until k = p.k, where it is a fold in
    names[0]; from there the curve in ``names``. Raises OrbitError when that path meets
    the Hopf curve first (a Bautin point: no fold in names[0] at this k; at tau = 10 the
    fold in k moves from 1.214 at d = 1e-4 to the Hopf curve at d = 2.23, k = 6.41)."""
    name = names[0]
    in_k = start_at_fold(p, ("k", name), getattr(p, name), dt, step, max_step,
                         n_delay=n_delay)
    in_k.first()
    along = switched(in_k, (name, "k"), p.k, step, max_step)
    for _ in walk(along, p.k, 400):
        pass
    if not along.end.startswith("reached"):
        raise OrbitError(f"no fold of cycles in {name} at k = {p.k:g}: from the fold in k at "
                         f"{name} = {getattr(p, name):g} the fold surface ended at {name} = "
                         f"{along.points[-1].first:.6g}, k = {along.points[-1].second:.6g} "
                         f"({along.end})")
    return switched(along, names, reach, step, max_step)
