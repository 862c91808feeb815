"""Branch switching at a period doubling: the branch of orbits of period 2T born there.

At a period doubling the orbit (z*, T*) at p* has a multiplier -1 with eigenvector v. The
orbit traversed twice is a solution of period 2T* whose map has +1 there instead: the
period-doubled orbits branch off it along v, with p - p* growing as the square of their
distance along v (a pitchfork of the second iterate). The new branch starts as
core.continuation's Hopf start does: from (z* + eps v, 2T*, p*), with its first tangent
along (v, 0, 0), so that the arclength condition holds the component along v at eps and
Newton cannot fall back onto the doubled old orbit. The distance of an orbit of period
2T to its own half-period shift, zero on the doubled old orbit, measures how far the
branch has left it (``half_shift``).
"""

from __future__ import annotations

import itertools
import math

import numpy as np
from scipy.sparse.linalg import ArpackNoConvergence, LinearOperator, eigs

from core.continuation import Bifurcation, Branch, grid_at, params_at
from core.floquet import ARNOLDI_VECTORS, ARPACK_SEED, ARPACK_TOL
from core.orbit import OrbitError, PeriodMap, Shot
from core.shooting import correct, weighted_dot

#: The first orbit's distance from the doubled one along the eigenvector (weighted norm):
#: far enough from it for the bordered Newton system not to be near singular there, near
#: enough for the quadratic branch to hold (b at tau = 2, k = 12, dt = 0.0025: the first
#: orbit has half-period shift 0.023, the next ones grow as sqrt(b - b_0), slope 0.47).
SWITCH_EPS = 1e-2
#: Multipliers asked of ARPACK to find the one at -1 with its eigenvector.
SWITCH_MULTIPLIERS = 6


def orbit_at(branch: Branch, value: float, after: int | None = None
             ) -> tuple[PeriodMap, np.ndarray, float, Shot]:
    """The orbit of ``branch`` at parameter ``value``: corrected (parameter fixed) from the
    linear interpolation of the two walked points around it (the first such pair, or the
    points ``after`` - 1 and ``after``: a branch past a fold passes a value more than
    once), or OrbitError if none are."""
    n = branch.g0.size
    pairs = list(itertools.pairwise(branch.states))
    if after is not None:
        pairs = pairs[after - 1:after]
    for (ya, _), (yb, _) in pairs:
        pa, pb = float(ya[-1]), float(yb[-1])
        if (pa - value) * (pb - value) <= 0 and pa != pb:
            s = (value - pa) / (pb - pa)
            y = ya + s * (yb - ya)
            pm = branch.map_at(value)
            shot = pm.shoot(y[:n], float(y[n]))
            sol = correct(pm, y[:n], float(y[n]), y[:n], shot.d_dT)
            return pm, sol.z, sol.period, sol.shot
    raise OrbitError(f"the branch does not pass {branch.name} = {value:.6g}")


def multiplier_vector(pm: PeriodMap, shot: Shot, target: complex
                      ) -> tuple[complex, np.ndarray]:
    """The multiplier nearest ``target`` of the orbit through ``shot`` and its eigenvector
    (complex, unit in the weighted norm, phase fixed by its largest entry: real there)."""
    n = pm.g.size
    sw = np.sqrt(pm.g.weights)

    def mv(x: np.ndarray) -> np.ndarray:
        return sw * pm.tangent(shot, np.asarray(x).ravel() / sw)

    op = LinearOperator((n, n), matvec=mv, dtype=float)
    k = min(SWITCH_MULTIPLIERS, n - 3)
    start = np.random.default_rng(ARPACK_SEED).standard_normal(n)
    try:
        values, vectors = eigs(op, k=k, which="LM", tol=ARPACK_TOL,
                               ncv=min(n - 1, max(3 * k, ARNOLDI_VECTORS)), v0=start)
    except ArpackNoConvergence as exc:
        raise OrbitError("Arnoldi did not converge on the monodromy operator") from exc
    i = int(np.argmin(np.abs(values - target)))
    v = vectors[:, i] / sw
    v = v * np.exp(-1j * np.angle(v[int(np.argmax(np.abs(v)))]))
    v /= math.sqrt(float(np.sum(pm.g.weights * np.abs(v) ** 2)))
    return complex(values[i]), v


def flip_vector(pm: PeriodMap, shot: Shot) -> tuple[complex, np.ndarray]:
    """The multiplier nearest -1 of the orbit through ``shot`` and its eigenvector (real,
    unit in the weighted norm, sign fixed by its largest entry)."""
    mu, v = multiplier_vector(pm, shot, -1.0)
    r = np.real(v)
    return mu, r / math.sqrt(weighted_dot(r, r, pm.g.weights))


def period_doubled(branch: Branch, pd: Bifurcation, eps: float = SWITCH_EPS,
                   step: float | None = None, max_step: float | None = None) -> Branch:
    """The branch of period-2T orbits born at the period doubling ``pd`` of ``branch``,
    its first orbit corrected (eps along the flip eigenvector, the parameter free); walk
    it with core.continuation.walk. Steps default to the old branch's."""
    if pd.type != "period-doubling":
        raise ValueError(f"branch switching needs a period doubling, not a {pd.type}")
    pm, z, period, shot = orbit_at(branch, pd.value)
    mu, v = flip_vector(pm, shot)
    if abs(mu.imag) > 1e-6 or abs(mu + 1.0) > 1e-2:
        raise OrbitError(f"no multiplier at -1 at {branch.name} = {pd.value:.8g} (nearest "
                         f"{mu.real:.6f}{mu.imag:+.6f}i)")
    q = params_at(branch.base, branch.name, pd.value)
    g = grid_at(branch.g0, q, branch.name)
    z0 = z + eps * v
    y0 = np.concatenate((z0, [2 * period, pd.value]))
    t = np.concatenate((v, [0.0, 0.0]))
    doubled = PeriodMap(q, g)
    first = doubled.shoot(z0, 2 * period)
    h = branch.max_step if step is None else step
    new = Branch(q, g, branch.name, y0, t, first, h, branch.max_step if max_step is None
                 else max_step)
    y, shot2, _ = new._correct(y0, z0, first.d_dT)
    new.y, new.shot = y, shot2
    return new


def half_shift(pm: PeriodMap, z: np.ndarray, period: float) -> float:
    """The weighted distance of the orbit (z, period) from itself half a period later:
    zero on an orbit of period T traversed twice (period = 2T), the size of the
    period-doubled part on a period-doubled orbit."""
    d = pm.shoot(z, period / 2).value - z
    return math.sqrt(weighted_dot(d, d, pm.g.weights))


__all__ = ["SWITCH_EPS", "flip_vector", "half_shift", "multiplier_vector", "orbit_at",
           "period_doubled"]
