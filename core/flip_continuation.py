"""The period doubling (flip) of cycles continued as a curve in two parameters, by the fold
curve's machinery (core.fold_continuation) with its own test function.

At a period doubling the monodromy dP/dz has the multiplier -1: dP/dz + I is singular,
while the orbit's own Jacobian F_x stays regular. The test function g is the last unknown of

    [ dP/dz + I   c ] [v]   [0]
    [ c^T         0 ] [g] = [1]                               (minimally augmented)

with c the flip eigenvector at the previous point (its left eigenvector is not orthogonal to
it where -1 is simple, so the border is regular); g vanishes exactly where -1 is a
multiplier. The orbit's rows are solved with F_x itself:

    d0 = F_x^-1 (-F),   phi1 = (F_x^-1 (-F_p), 1, 0),   phi2 = (F_x^-1 (-F_q), 0, 1),

and Newton, the steps and the resume are the fold curve's. Products with dP/dz only, as
there. Its ``curvature`` is Dg.phi1: how fast the multiplier moves through -1 along p.
"""

from __future__ import annotations

import math
from typing import ClassVar

import numpy as np

from core.branch_start import BranchSpec
from core.branch_switch import flip_vector, orbit_at
from core.continuation import Bifurcation, Branch
from core.first_crossing import first_crossing, start_at_crossing
from core.fold_continuation import BORDER_RTOL, CurvePoint, FoldCurve, LinearParts
from core.orbit import PeriodMap, Shot
from core.params import Params
from core.shooting import solve_krylov, weighted_dot


class FlipCurve(FoldCurve):
    """The period doubling in ``names[0]`` continued in ``names[1]``; ``c`` is the flip
    eigenvector (the reduced state's size)."""

    what: ClassVar[str] = "period-doubling"

    def _orbit_solve(self, pm: PeriodMap, shot: Shot, rhs: np.ndarray) -> np.ndarray:
        """F_x x = rhs for x = (dz, dT): the orbit's Jacobian with its phase row."""
        n = self.size
        w = np.concatenate((pm.g.weights, [1.0]))
        sw = np.sqrt(w)

        def apply(x: np.ndarray) -> np.ndarray:
            d = x / sw
            dz, dT = d[:n], d[n]
            top = pm.tangent(shot, dz) - dz + shot.d_dT * dT
            return np.concatenate((sw[:n] * top,
                                   [weighted_dot(self.zdot_ref, dz, pm.g.weights)]))

        x, _ = solve_krylov(apply, np.concatenate((sw[:n] * rhs[:n], rhs[n:])), BORDER_RTOL)
        return x / sw

    def _g(self, y: np.ndarray, x0: np.ndarray | None = None) -> tuple[float, np.ndarray]:
        """g at y, and the bordered solution (v, g), v the flip eigenvector's estimate."""
        n = self.size
        _, shot, pm = self._F(y)
        w = np.concatenate((pm.g.weights, [1.0]))
        sw = np.sqrt(w)
        c = self.c

        def apply(x: np.ndarray) -> np.ndarray:
            d = x / sw
            v, gg = d[:n], d[n]
            top = pm.tangent(shot, v) + v + c * gg
            return np.concatenate((sw[:n] * top, [weighted_dot(c, v, pm.g.weights)]))

        rhs = np.zeros(n + 1)
        rhs[-1] = 1.0
        guess = None if x0 is None else x0 * sw
        x, _ = solve_krylov(apply, rhs, BORDER_RTOL, x0=guess)
        x = x / sw
        return float(x[-1]), x

    def _orbit_parts(self, y: np.ndarray, free_q: bool
                     ) -> tuple[np.ndarray, Shot, np.ndarray, np.ndarray, np.ndarray | None]:
        """F at y and the orbit rows' solutions d0, phi1, phi2 (the module doc)."""
        n = self.size
        F, shot, pm = self._F(y)
        d0 = np.concatenate((self._orbit_solve(pm, shot, -F), [0.0, 0.0]))
        phi1 = np.concatenate((self._orbit_solve(pm, shot, -self._dF(y, n + 1)), [1.0, 0.0]))
        phi2 = None
        if free_q:
            phi2 = np.concatenate((self._orbit_solve(pm, shot, -self._dF(y, n + 2)),
                                   [0.0, 1.0]))
        return F, shot, d0, phi1, phi2

    def _linear(self, y: np.ndarray, free_q: bool) -> LinearParts:
        F, shot, d0, phi1, phi2 = self._orbit_parts(y, free_q)
        g, null = self._g(y)
        return LinearParts(F, g, d0, phi1, phi2, shot, null)

    def ended(self, point: CurvePoint) -> str:
        """A period-doubling curve goes on at any amplitude (it has no Hopf end)."""
        return ""

    def _border(self, null: np.ndarray, pm: PeriodMap) -> np.ndarray:
        v = null[:self.size]
        return v / math.sqrt(weighted_dot(v, v, pm.g.weights))




def start_at_flip(spec_params: Params, names: tuple[str, str], dt: float, end: float,
                  reach: float, step: float = 0.05, max_step: float = 0.5,
                  hopf_branch: int = 1, max_points: int = 400, branch_step: float = 0.5
                  ) -> FlipCurve:
    """The curve's start: the first real period doubling on the branch in names[0] from
    the Hopf point (``first_flip``), continued in names[1] (``flip_curve_at``) towards
    ``reach`` (core.first_crossing.start_at_crossing)."""
    return start_at_crossing(first_flip, flip_curve_at, spec_params, names, dt, end, reach,
                             step, max_step, hopf_branch, max_points, branch_step)


def first_flip(spec_params: Params, name: str, dt: float, end: float, hopf_branch: int = 1,
               max_points: int = 400, branch_step: float = 0.5
               ) -> tuple[Branch, Bifurcation, int]:
    """The one-parameter branch in ``name`` from the Hopf point at ``spec_params`` walked
    towards ``end`` (steps of at most ``branch_step``) until a multiplier crosses -1 for real
    (core.first_crossing): the branch, that period doubling and the index of the point
    after it. OrbitError when the branch ends, or passes ``end``, with none."""
    spec = BranchSpec(spec_params, name, dt, True, end, max_points, branch_step, hopf_branch)
    return first_crossing(spec, "period-doubling",
                          lambda mu: mu.real < 0 and abs(mu.imag) < 1e-6)


def flip_curve_at(branch: Branch, pd: Bifurcation, second: str, step: float = 0.05,
                  max_step: float = 0.5, after: int | None = None) -> FlipCurve:
    """The period doubling ``pd`` of ``branch`` (between its points ``after`` - 1 and
    ``after``, if given: a branch past a fold passes a value more than once) as the start
    of its curve in (branch.name, ``second``): its orbit (core.branch_switch.orbit_at) with
    the flip eigenvector as the border; ``first()`` corrects it onto the period doubling
    with ``second`` fixed."""
    pm, z, period, shot = orbit_at(branch, pd.value, after)
    _, v = flip_vector(pm, shot)
    q = pm.p
    y0 = np.concatenate((z, [period, pd.value, getattr(q, second)]))
    return FlipCurve(q, (branch.name, second), branch.g0.n_delay, pm.g.dt, y0, v, z.copy(),
                     shot.d_dT.copy(), step, max_step)


__all__ = ["FlipCurve", "first_flip", "flip_curve_at", "start_at_flip"]
