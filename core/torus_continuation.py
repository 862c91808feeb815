"""The Neimark-Sacker (torus) bifurcation of cycles continued as a curve in two parameters,
by the fold curve's machinery (core.fold_continuation) with its own test functions.

At a torus bifurcation the monodromy M = dP/dz has a pair of multipliers exp(+-i theta) on
the unit circle, so with kappa = cos theta the matrix

    A(kappa) = M^2 - 2 kappa M + I                                  (its kernel: the pair's
                                                                     real invariant plane)

has a two-dimensional kernel. The test functions are the 2 x 2 block G of the bordered
system

    [ A(kappa)  B ] [V]   [0 ]
    [ B^T W     0 ] [G] = [I2]                                    (minimally augmented)

with B two columns spanning that plane at the previous point (weighted-orthonormal): G = 0
exactly where A(kappa) has the two-dimensional kernel (Govaerts, Kuznetsov et al., MatCont's
torus of cycles). kappa is one more unknown, so two of G's four entries are solved for; which
two is chosen at every Newton step as the pair whose Jacobian in (p, kappa) (and q, with
the arclength row) is best conditioned (far from the 1:2 resonance G is a rotation-scaling
block whose diagonal entries are equal; next to it the pair's plane is nearly a Jordan
block and an off-diagonal entry decides kappa). The other two entries vanish with them
on the curve; the point's ``G`` residual reports all four.

Why kappa and not the complex multiplier exp(i theta) itself: the tori of this model sit
next to strong resonances (core.multiplier_crossing's ``resonance``). On the 2-slip branch
at tau = 10 the pair is -0.99999989 +- 0.00047 i: the multiplier and its conjugate are 1e-3
apart, where a complex bordered system in the multiplier is that badly conditioned and
fails at the 1:2 point itself; A(kappa) stays regular through it (beyond, kappa < -1, it
continues the neutral saddle, not a torus: the walk ends there, ``step``). On the 3-slip
branch a second pair sits 1.4e-3 away at nearly the same angle (both near the cube roots
of unity): A(kappa) is then nearly singular on that pair too (singular values ~2e-3), which
GMRES resolves; the border keeps to the crossing pair's plane.

The orbit's rows are solved with F_x (regular at a torus) as on the flip curve; Newton
solves for (s1, s2, dkappa) with G's derivatives by forward differences (each one two
bordered GMRES solves, a product with A being two with M). Nothing here needs M's
transpose.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import replace
from typing import ClassVar

import numpy as np

from core.branch_start import BranchSpec
from core.branch_switch import multiplier_vector, orbit_at
from core.continuation import Bifurcation, Branch
from core.first_crossing import first_crossing, start_at_crossing
from core.flip_continuation import FlipCurve
from core.fold_continuation import CURVE_NEWTON, CURVE_TOL, FD_REL, CurvePoint, LinearParts
from core.orbit import Grid, OrbitError, PeriodMap
from core.params import Params
from core.shooting import solve_krylov, weighted_dot

#: Newton's tolerance on G's entries. Unlike a fold's g, G is linear in the distance from
#: the curve: |mu| - 1 is about G / 2, and on the 2-slip branch at tau = 10 |mu| moves by
#: 1.6e-3 per unit of k, so 1e-10 places the torus to ~3e-8 in k.
TORUS_G_TOL = 1e-10
#: The walk ends where kappa leaves (-1, 1) by more than this: the pair has met on the real
#: axis (a 1:1 or 1:2 resonance) and the curve goes on as a neutral saddle, not a torus.
KAPPA_MARGIN = 1e-9
#: GMRES's relative tolerance for the torus's bordered solves, tighter than a fold's
#: (BORDER_RTOL): with the 3-slip orbit's second pair ~1e-3 from the crossing one, G's
#: noise at 1e-11 was 1e-10 to 1e-9 and Newton stalled above TORUS_G_TOL; at 1e-12 it
#: converges in three steps (1.4e-4, 2.5e-7, 2e-9, 5e-12), and the points agree with
#: those at 1e-13 to 1e-9 in k.
TORUS_RTOL = 1e-12


class TorusCurve(FlipCurve):
    """The torus bifurcation in ``names[0]`` continued in ``names[1]``. ``c`` holds the
    border's two columns (the reduced state's size each) and kappa, in that order."""

    what: ClassVar[str] = "torus"
    #: Its Newton converges linearly, by ~1e-2 a step (G's forward differences carry
    #: GMRES's noise): three steps is an easy point here.
    easy: ClassVar[int] = 3

    @property
    def kappa(self) -> float:
        return float(self.c[-1])

    def _columns(self) -> tuple[np.ndarray, np.ndarray]:
        n = self.size
        return self.c[:n], self.c[n:2 * n]

    def _G(self, y: np.ndarray, kappa: float, x0: np.ndarray | None = None
           ) -> tuple[np.ndarray, np.ndarray]:
        """G's entries (G11, G21, G12, G22) at (y, kappa), and the two bordered solutions as
        one vector, (v1, G11, G21, v2, G12, G22): where the next solves start."""
        n = self.size
        _, shot, pm = self._F(y)
        w = np.concatenate((pm.g.weights, [1.0, 1.0]))
        sw = np.sqrt(w)
        b1, b2 = self._columns()

        def apply(x: np.ndarray) -> np.ndarray:
            d = x / sw
            v = d[:n]
            mv = pm.tangent(shot, v)
            top = pm.tangent(shot, mv) - 2.0 * kappa * mv + v + b1 * d[n] + b2 * d[n + 1]
            return np.concatenate((sw[:n] * top, [weighted_dot(b1, v, pm.g.weights),
                                                  weighted_dot(b2, v, pm.g.weights)]))

        out = []
        for j in range(2):
            rhs = np.zeros(n + 2)
            rhs[n + j] = 1.0
            guess = None if x0 is None else x0[j * (n + 2):(j + 1) * (n + 2)] * sw
            x, _ = solve_krylov(apply, rhs, TORUS_RTOL, x0=guess)
            out.append(x / sw)
        return np.array([out[0][n], out[0][n + 1], out[1][n], out[1][n + 1]]), \
            np.concatenate(out)

    def _dG(self, y: np.ndarray, kappa: float, G: np.ndarray, d: np.ndarray | None,
            x0: np.ndarray) -> np.ndarray:
        """G's derivative along d (kappa fixed), or in kappa (d None): a forward difference."""
        if d is None:
            eps = FD_REL
            return (self._G(y, kappa + eps, x0)[0] - G) / eps
        size = math.sqrt(weighted_dot(d, d, self.weights()))
        if size == 0.0:
            return np.zeros(4)
        eps = FD_REL * max(1.0, math.sqrt(weighted_dot(y, y, self.weights()))) / size
        return (self._G(y + eps * d, kappa, x0)[0] - G) / eps

    def correct(self, y_pred: np.ndarray, t: np.ndarray | None
                ) -> tuple[np.ndarray, int, float, LinearParts]:
        """Newton on (F, two of G's entries) for (y, kappa) from (y_pred, the last kappa):
        with the arclength row along t, or with q fixed (t None). Returns the point, the
        steps, NaN (a torus has no quadratic coefficient) and the solves there, whose
        ``null`` is (V's columns, kappa) for the next border."""
        y, kappa = y_pred.copy(), self.kappa
        w = self.weights()
        x0: np.ndarray | None = None
        for step in range(CURVE_NEWTON + 1):
            F, shot, d0, phi1, phi2 = self._orbit_parts(y, t is not None)
            G, x0 = self._G(y, kappa, x0)
            arc = 0.0 if t is None else weighted_dot(t, y - y_pred, w)
            res = math.sqrt(weighted_dot(F, F, np.concatenate(
                (Grid(1.0, self.n_delay).weights, [1.0]))) + arc * arc)
            if res < CURVE_TOL and float(np.abs(G).max()) < TORUS_G_TOL:
                null = np.concatenate((x0[:self.size], x0[self.size + 2:2 * self.size + 2],
                                       [kappa]))
                return y, step, math.nan, LinearParts(F, float(np.abs(G).max()), d0, phi1,
                                                      phi2, shot, null)
            if step == CURVE_NEWTON:
                break
            columns = [self._dG(y, kappa, G, phi1, x0), self._dG(y, kappa, G, None, x0)]
            rhs = G + self._dG(y, kappa, G, d0, x0)
            if phi2 is not None and t is not None:
                columns.insert(1, self._dG(y, kappa, G, phi2, x0))
            J = np.column_stack(columns)          # 4 entries x (s1, [s2,] dkappa)
            if t is not None:
                assert phi2 is not None
                arc_row = [weighted_dot(t, phi1, w), weighted_dot(t, phi2, w), 0.0]
                s = _solve_best(J, rhs, np.array(arc_row),
                                arc + weighted_dot(t, d0, w))
                y = y + d0 + s[0] * phi1 + s[1] * phi2
            else:
                s = _solve_best(J, rhs)
                y = y + d0 + s[0] * phi1
            kappa += float(s[-1])
            if y[self.size] <= 0:
                raise OrbitError("the period left the positive range")
        raise OrbitError(f"the torus curve's Newton did not converge at {self.names[0]} = "
                         f"{float(y[-2]):.6g}, {self.names[1]} = {float(y[-1]):.6g}")

    def _accept(self, y: np.ndarray, steps: int, curvature: float,
                lin: LinearParts) -> CurvePoint:
        point = replace(super()._accept(y, steps, curvature, lin), kappa=self.kappa)
        self.points[-1] = point
        return point

    def ended(self, point: CurvePoint) -> str:
        """The walk ends where kappa leaves (-1, 1) (KAPPA_MARGIN): the pair has met on the
        real axis, at -1 (the 1:2 resonance) or +1 (1:1), and the curve beyond is a neutral
        saddle's (its last point is already one: core.codim2 places the resonance)."""
        if abs(point.kappa) <= 1.0 + KAPPA_MARGIN:
            return ""
        at = "-1 (the 1:2 resonance)" if point.kappa < 0 else "+1 (the 1:1 resonance)"
        return (f"the torus multipliers met on the real axis at {at}: kappa = "
                f"{point.kappa:.10g}, past it a neutral saddle, not a torus")

    def _border(self, null: np.ndarray, pm: PeriodMap) -> np.ndarray:
        """The next border: V's columns made weighted-orthonormal, then kappa."""
        n = self.size
        b1, b2 = _orthonormal(null[:n], null[n:2 * n], pm.g.weights)
        return np.concatenate((b1, b2, [null[-1]]))

    def _first_tangent(self) -> np.ndarray:
        """The curve's direction at the first point: d = s1 phi1 + phi2 (with its dkappa)
        in the null space of the Jacobian of the two best entries of G, oriented by
        ``direction``."""
        _, _, _, phi1, phi2 = self._orbit_parts(self.y, True)
        assert phi2 is not None
        kappa = self.kappa
        G, x0 = self._G(self.y, kappa)
        d1, d2 = self._dG(self.y, kappa, G, phi1, x0), self._dG(self.y, kappa, G, phi2, x0)
        dk = self._dG(self.y, kappa, G, None, x0)
        s = _solve_best(np.column_stack((d1, dk)), d2)   # s1 phi1 + phi2 keeps G at 0
        t = phi2 + s[0] * phi1
        t /= math.sqrt(weighted_dot(t, t, self.weights()))
        return t if t[-1] * self.direction > 0 else -t


def _solve_best(J: np.ndarray, rhs: np.ndarray, extra_row: np.ndarray | None = None,
                extra_rhs: float = 0.0) -> np.ndarray:
    """Solve two of J's four rows (J s = -rhs), the pair whose square system (with
    ``extra_row`` below, if given) is best conditioned; J's columns are the unknowns."""
    best: tuple[float, np.ndarray, np.ndarray] | None = None
    for a, b in itertools.combinations(range(4), 2):
        rows = [J[a], J[b]] if extra_row is None else [J[a], J[b], extra_row]
        m = np.array(rows)
        r = np.array([rhs[a], rhs[b]] + ([] if extra_row is None else [extra_rhs]))
        cond = np.linalg.cond(m)
        if best is None or cond < best[0]:
            best = (cond, m, r)
    assert best is not None
    return np.linalg.solve(best[1], -best[2])


def _orthonormal(a: np.ndarray, b: np.ndarray, weights: np.ndarray
                 ) -> tuple[np.ndarray, np.ndarray]:
    """Gram-Schmidt in the weighted product."""
    a = a / math.sqrt(weighted_dot(a, a, weights))
    b = b - weighted_dot(a, b, weights) * a
    return a, b / math.sqrt(weighted_dot(b, b, weights))


def first_torus(spec_params: Params, name: str, dt: float, end: float, hopf_branch: int = 1,
                max_points: int = 400, branch_step: float = 0.5
                ) -> tuple[Branch, Bifurcation, int]:
    """The one-parameter branch in ``name`` from the ``hopf_branch``-th Hopf point walked
    towards ``end`` until a complex pair crosses the unit circle for real
    (core.first_crossing): the branch, that torus, and the index of the point after it.
    OrbitError when the branch ends, or passes ``end``, with none."""
    spec = BranchSpec(spec_params, name, dt, True, end, max_points, branch_step, hopf_branch)
    return first_crossing(spec, "torus", lambda mu: abs(mu.imag) > 1e-6)


def torus_curve_at(branch: Branch, ns: Bifurcation, second: str, step: float = 0.05,
                   max_step: float = 0.5, after: int | None = None) -> TorusCurve:
    """The torus ``ns`` of ``branch`` (between its points ``after`` - 1 and ``after``, if
    given: the 2-slip branch passes k = 5.2567 before its fold and after it) as the start
    of its curve in (branch.name, ``second``): its orbit, the border from the crossing
    pair's eigenvector, kappa = cos(arg mu); ``first()`` corrects it onto the torus with
    ``second`` fixed."""
    pm, z, period, shot = orbit_at(branch, ns.value, after)
    mu, v = multiplier_vector(pm, shot, ns.multiplier)
    if abs(mu.imag) == 0.0:
        raise OrbitError(f"no complex pair at {branch.name} = {ns.value:.8g} (nearest "
                         f"multiplier {mu.real:.6f})")
    b1, b2 = _orthonormal(v.real.copy(), v.imag.copy(), pm.g.weights)
    q = pm.p
    y0 = np.concatenate((z, [period, ns.value, getattr(q, second)]))
    c = np.concatenate((b1, b2, [mu.real / abs(mu)]))
    return TorusCurve(q, (branch.name, second), branch.g0.n_delay, pm.g.dt, y0, c, z.copy(),
                      shot.d_dT.copy(), step, max_step)


def start_at_torus(spec_params: Params, names: tuple[str, str], dt: float, end: float,
                   reach: float, step: float = 0.05, max_step: float = 0.5,
                   hopf_branch: int = 1, max_points: int = 400, branch_step: float = 0.5
                   ) -> TorusCurve:
    """The curve's start: the first real torus on the branch in names[0] from the Hopf
    point (``first_torus``), continued in names[1] (``torus_curve_at``) towards ``reach``
    (core.first_crossing.start_at_crossing)."""
    return start_at_crossing(first_torus, torus_curve_at, spec_params, names, dt, end, reach,
                             step, max_step, hopf_branch, max_points, branch_step)


__all__ = ["TorusCurve", "first_torus", "start_at_torus", "torus_curve_at"]
