"""Floquet multipliers of a periodic orbit: the leading eigenvalues of the monodromy dP/dz.

Matrix-free Arnoldi (ARPACK through scipy), one tangent integration over a period per
product. Two multipliers are exactly 1 for this model: the flow direction (a shift along
the orbit) and the translation of m_x. The reduced state has dropped the translation, so
its multiplier is measured apart, in full coordinates (core.orbit.PeriodMap
.translation_multiplier); the flow multiplier is the eigenvalue nearest 1, and its
distance from 1 is reported as a check of the orbit's accuracy. Stability and the type
of a crossing of the unit circle follow from the others: +1 a fold, -1 a period
doubling, a complex pair a torus (Neimark-Sacker).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.sparse.linalg import ArpackNoConvergence, LinearOperator, eigs

from core.orbit import OrbitError, PeriodMap, Shot

#: Multipliers computed (the issue's "leading ten").
N_MULTIPLIERS = 10
#: Arnoldi vectors. At large delay many multipliers crowd just inside the unit circle
#: (tau = 60 near the Hopf point: 1, 1, 0.99998 (pair), 0.99988 (pair), 0.99961, ...), and
#: with 30 vectors ARPACK needed 24,000 products (31 s) to separate the leading six; with
#: 150 it needs 294 (1.3 s). At tau = 10 (2004 unknowns) 150 vectors cost no more.
ARNOLDI_VECTORS = 150
#: ARPACK's relative accuracy of the eigenvalues, and the seed of its start vector.
ARPACK_TOL = 1e-10
ARPACK_SEED = 20261201
#: The flow multiplier must be this close to 1, or it is not among the multipliers
#: computed: the n-slip orbits (core.orbit_seed) have 2 (n - 1) multipliers near the circle
#: and, once unstable, several outside it, all above the flow's in modulus (k = 18,
#: tau = 10, n = 6: ten of modulus 1.0007 to 1.027, so the leading ten held no flow
#: multiplier and the one nearest 1 was 1.0007's pair, 1e-0 off). Measured distance of the
#: flow multiplier from 1 on these orbits: 2.1e-7 at dt = 0.01 (n = 3), 2.4e-8 at 0.005.
FLOW_TOL = 1e-4
#: The most multipliers the search for the flow's asks for: the 6-slip orbit needs 20
#: (ten above the flow's); past this the one nearest 1 is taken, as before the search.
#: Unbounded, a continuation at tau = 54 (heading's, 1204 unknowns) doubled to the whole
#: state and ARPACK refused its sizes (ncv = n - 1 = k + 1): a run of the reproduction
#: report failed so.
MAX_MULTIPLIERS = 80
#: A multiplier counts as on the unit circle within this distance (the flow multiplier's
#: own distance from 1 is ~1e-9 at dt = 0.01: RK4's accuracy over a period).
UNIT_TOL = 1e-6


@dataclass(frozen=True)
class Multipliers:
    """The leading multipliers (by modulus, descending), which one is the flow's, and the
    translation multiplier."""

    values: np.ndarray
    flow_index: int
    translation: float

    @property
    def flow(self) -> complex:
        return complex(self.values[self.flow_index])

    @property
    def nontrivial(self) -> np.ndarray:
        return np.delete(self.values, self.flow_index)

    @property
    def stable(self) -> bool:
        """All multipliers but the flow's strictly inside the unit circle."""
        others = self.nontrivial
        return bool(others.size == 0 or np.abs(others).max() < 1.0)

    def verdict(self, tol: float = UNIT_TOL) -> str:
        """"unstable" with a nontrivial multiplier outside the circle by more than tol,
        "marginal" with one within tol of it (on the circle to the accuracy: the 2-slip
        orbit at k = 20, tau = 10 has -1.00000000, at dt = 0.01 and 0.005 alike, where the
        flow multiplier is 4e-7 and 5e-8 from 1), "stable" otherwise."""
        moduli = np.abs(self.nontrivial)
        if np.any(moduli > 1.0 + tol):
            return "unstable"
        if np.any(moduli >= 1.0 - tol):
            return "marginal"
        return "stable"

    @property
    def unstable_count(self) -> int:
        return int(np.sum(np.abs(self.nontrivial) > 1.0))

    @property
    def leading(self) -> complex:
        """The largest nontrivial multiplier: the one that crosses first."""
        others = self.nontrivial
        return complex(others[0]) if others.size else 0j


def multipliers(pm: PeriodMap, shot: Shot, count: int = N_MULTIPLIERS,
                vectors: int = ARNOLDI_VECTORS, restarts: int = 2000) -> Multipliers:
    """The ``count`` leading Floquet multipliers of the orbit through ``shot`` (Arnoldi
    with ``vectors`` vectors, at least 3 count, restarted at most ``restarts`` times),
    more (doubling ``count``, up to MAX_MULTIPLIERS) until the flow multiplier is among
    them (FLOW_TOL)."""
    while True:
        m = _leading(pm, shot, count, vectors, restarts)
        if abs(m.flow - 1.0) < FLOW_TOL or count >= min(MAX_MULTIPLIERS, pm.g.size - 3):
            return m
        count = min(2 * count, MAX_MULTIPLIERS)


def _leading(pm: PeriodMap, shot: Shot, count: int, vectors: int, restarts: int) -> Multipliers:
    """The ``count`` leading multipliers, the one nearest 1 taken for the flow's."""
    n = pm.g.size
    sw = np.sqrt(pm.g.weights)

    def mv(x: np.ndarray) -> np.ndarray:
        return sw * pm.tangent(shot, np.asarray(x).ravel() / sw)

    op = LinearOperator((n, n), matvec=mv, dtype=float)
    k = min(count, n - 3)  # ARPACK's k + 1 < ncv <= n - 1
    # ARPACK starts from a random vector unless given one: a fixed start makes the
    # multipliers reproducible to the bit (a resumed branch, a rerun, the CLI and a worker)
    start = np.random.default_rng(ARPACK_SEED).standard_normal(n)
    try:
        values = eigs(op, k=k, which="LM", tol=ARPACK_TOL, ncv=min(n - 1, max(3 * k, vectors)),
                      v0=start, return_eigenvectors=False, maxiter=restarts)
    except ArpackNoConvergence as exc:
        raise OrbitError("Arnoldi did not converge on the monodromy operator") from exc
    values = values[np.argsort(-np.abs(values), kind="stable")]
    flow_index = int(np.argmin(np.abs(values - 1.0)))
    return Multipliers(values, flow_index, pm.translation_multiplier(shot))
