"""Newton-Krylov shooting for a periodic orbit: P(z, T) = z with a phase condition.

Each Newton step solves, matrix-free, by GMRES

    [ dP/dz - I     dP/dT ] [dz]     [ P(z, T) - z         ]
    [ zdot_ref^T W    0   ] [dT] = - [ <zdot_ref, z - z_ref> ]

(and, in a continuation, a third block row and column for the parameter: core.continuation
hands ``extra`` columns and rows). The variables are scaled by sqrt(W) (core.orbit's weights)
so that GMRES's Euclidean norm is the weighted one. With T > tau, dP/dz is compact-like
(a delay equation smooths over a delay) and GMRES needs tens of products per step.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.sparse.linalg import LinearOperator, gmres

from core.orbit import GMRES_RTOL, NEWTON_MAX, NEWTON_TOL, OrbitError, PeriodMap, Shot

#: GMRES's restart length and its total budget of products per Newton step.
KRYLOV_RESTART = 400
KRYLOV_MAX_PRODUCTS = 800


@dataclass
class Solution:
    """A corrected periodic orbit: reduced state, period, the last shot, and how Newton
    went (steps taken, final residual, Krylov products used)."""

    z: np.ndarray
    period: float
    shot: Shot
    steps: int
    residual: float
    products: int


def weighted_dot(a: np.ndarray, b: np.ndarray, w: np.ndarray) -> float:
    return float(np.dot(a * w, b))


def solve_krylov(apply: Callable[[np.ndarray], np.ndarray], rhs: np.ndarray,
                 rtol: float, max_products: int = KRYLOV_MAX_PRODUCTS,
                 x0: np.ndarray | None = None) -> tuple[np.ndarray, int]:
    """GMRES on a matrix-free operator (from x0, when given: a nearby solution); returns
    the solution and the products used (about max_products at most)."""
    count = [0]

    def mv(x: np.ndarray) -> np.ndarray:
        count[0] += 1
        return apply(np.asarray(x).ravel())

    n = rhs.size
    op = LinearOperator((n, n), matvec=mv, dtype=float)
    restart = min(KRYLOV_RESTART, max_products, n)
    x, info = gmres(op, rhs, x0=x0, rtol=rtol, atol=0.0, restart=restart,
                    maxiter=max(1, max_products // restart))
    if info < 0:
        raise OrbitError("GMRES broke down on the Newton system")
    return x, count[0]


def correct(pm: PeriodMap, z: np.ndarray, period: float, z_ref: np.ndarray,
            zdot_ref: np.ndarray, tol: float = NEWTON_TOL, max_steps: int = NEWTON_MAX,
            max_products: int = KRYLOV_MAX_PRODUCTS) -> Solution:
    """Newton-Krylov from (z, period) with the phase condition of (z_ref, zdot_ref), in at
    most max_steps steps of at most ~max_products Krylov products each (a budget)."""
    w = pm.g.weights
    sw = np.sqrt(w)
    n = z.size
    products = 0
    shot = pm.shoot(z, period)
    for step in range(max_steps + 1):
        r = shot.value - z
        phase = weighted_dot(zdot_ref, z - z_ref, w)
        residual = math.sqrt(weighted_dot(r, r, w) + phase * phase)
        if residual < tol:
            return Solution(z, period, shot, step, residual, products)
        if step == max_steps:
            break
        current = shot

        def apply(x: np.ndarray, current: Shot = current) -> np.ndarray:
            dz, dT = x[:n] / sw, x[n]
            top = pm.tangent(current, dz) - dz + current.d_dT * dT
            return np.concatenate((sw * top, [weighted_dot(zdot_ref, dz, w)]))

        rhs = -np.concatenate((sw * r, [phase]))
        x, used = solve_krylov(apply, rhs, min(GMRES_RTOL, 0.1 * residual), max_products)
        products += used
        dz, dT = x[:n] / sw, x[n]
        # a damped step when the full one does not lower the residual (far from the orbit)
        for lam in (1.0, 0.5, 0.25, 0.125):
            trial_z, trial_T = z + lam * dz, period + lam * dT
            if trial_T <= 0:
                continue
            try:
                trial = pm.shoot(trial_z, trial_T)
            except OrbitError:
                continue
            tr = trial.value - trial_z
            tp = weighted_dot(zdot_ref, trial_z - z_ref, w)
            if math.sqrt(weighted_dot(tr, tr, w) + tp * tp) < residual or lam == 0.125:
                z, period, shot = trial_z, trial_T, trial
                break
        else:
            raise OrbitError("Newton's step left the finite range: no orbit near the seed")
    raise OrbitError(f"Newton did not converge in {max_steps} steps (residual "
                     f"{residual:.1e} > {tol:.0e}): no periodic orbit near the seed")
