"""Linear stability of the rest state a run actually sits at: the sliding state with noise.

core.stability solves the noise-free fixed point (d = 0), where the characteristic function
factorises. With noise d > 0 the run rests at the steady state of core.hopf_start (a small
drift m_y = y*, s_y* = k s_x* > 0), where the variance block couples to the delay block and
the roots move: the Hopf point at tau = 60, d = 1e-4 lies at k = 5.97491 against 5.97735
without noise (tau = 10: 6.14619 against 6.14854). Between the two the noise-free root is
negative while the rest state is unstable. Here each noise-free root is carried to the
noisy state by Newton's method on

    f(lam) = det(lam I - J_0 - J_tau e^{-lam tau}) / lam

(J_0, J_tau: core.hopf_start.jacobians; the root lam = 0 of the m_x shift divided out), and
the largest real part is the rest state's exponent. At d = 0 that is
core.stability.leading_exponent itself.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from core.params import Params
from core.stability import hopf_k, leading_exponent, roots, variance_roots

#: A leading root whose real part lies within this of 0 decides nothing: the rest state's
#: stability is then below what the root computation resolves. Measured: at the exact Hopf
#: point k_H(tau) (core.stability.hopf_k) the noise-free root's real part is at most
#: 3.8e-15 over tau = 0.1-200 (3.8e-15 at tau = 0.1, where |lam| = 33; 4e-18 at tau = 10);
#: at the noisy Hopf point of core.hopf_start (found to |det| < 1e-13) this module's root
#: is at most ~1e-12 (tests/unit/test_unstable_rest.py). The margin of 100 covers the
#: Hopf point's own tolerance. A root of 1e-10 at tau = 60 is k - k_H ~ 2e-5.
NEUTRAL_TOL = 1e-10
#: Below this fraction of k_H(tau) (noise-free) the rest state counts as stable without a
#: root computation, for noise up to GATE_MAX_D: the first Hopf branch is the stability
#: boundary (core.stability), and the noise lowers it in proportion to d (core.hopf_start:
#: tau = 10: -0.038% at d = 1e-4, -0.38% at 1e-3, -3.6% at 1e-2, -25% at 0.1; tau = 2:
#: -0.012%, -0.12%, -1.2%, -9.9%); the gate leaves 2%. Noisier points are always computed.
STABLE_GATE = 0.98
GATE_MAX_D = 1e-3
#: Newton's step budget and relative tolerance on lam for the noisy roots.
NEWTON_STEPS, NEWTON_TOL = 60, 1e-14


def _det(lam: complex, j0: np.ndarray, jt: np.ndarray, tau: float) -> complex:
    """det(lam I - J_0 - J_tau e^{-lam tau}) / lam."""
    a = lam * np.eye(5) - j0 - jt * np.exp(-lam * tau)
    return complex(np.linalg.det(a)) / lam


def _carry(lam: complex, j0: np.ndarray, jt: np.ndarray, tau: float) -> complex | None:
    """Newton's method on _det from lam (a noise-free root); None when it does not converge."""
    for _ in range(NEWTON_STEPS):
        h = 1e-7 * max(1.0, abs(lam))
        f = _det(lam, j0, jt, tau)
        slope = (_det(lam + h, j0, jt, tau) - f) / h  # f is analytic: one direction suffices
        if slope == 0.0:
            return None
        step = f / slope
        lam -= step
        if abs(step) < NEWTON_TOL * max(1.0, abs(lam)):
            return lam
    return None


@dataclass(frozen=True, slots=True)
class RestRoot:
    """A root of the rest state's characteristic function (Im >= 0): ``factor`` "delay"
    for a root of h (eq. 20's delay factor, core.stability) or of its continuation to the
    noisy state, "variance" for the variance block's (eqs. 6c-6e)."""

    value: complex
    factor: str


def rest_roots(p: Params, count: int = 6) -> list[RestRoot]:
    """The rest state's rightmost roots, best first, the m_x shift's zero root left out:
    h's ``count`` rightmost (core.stability.roots) and the variance block's three, each
    carried to the noisy rest state when d > 0 (as rest_exponent carries them, with no
    gate). Raises ArithmeticError when a root cannot be carried."""
    delay = [RestRoot(complex(r), "delay") for r in _nonzero(roots(p.F1, p.k, p.tau, count + 1))]
    variance = [RestRoot(complex(r), "variance") for r in _nonzero(variance_roots(p))
                if r.imag >= 0.0]
    found = delay[:count] + variance
    if p.d > 0.0:
        from core.hopf_start import jacobians, steady_state  # the orbit kernels: as below
        from core.orbit import OrbitError
        try:
            ss = steady_state(p)
        except OrbitError as exc:
            raise ArithmeticError(str(exc)) from None
        j0, jt = jacobians(p, ss)
        carried = []
        for r in found:
            lam = r.value if abs(r.value.imag) >= 1e-12 else complex(r.value.real, 1e-9)
            moved = _carry(lam, j0, jt, p.tau)
            if moved is None:
                raise ArithmeticError(f"the root {r.value:.6g} of the noise-free state could not "
                                      f"be carried to the noisy one (d = {p.d:g})")
            if abs(moved.imag) < 1e-7:  # the nudge off the real axis, undone
                moved = complex(moved.real, 0.0)
            carried.append(RestRoot(complex(moved.real, abs(moved.imag)), r.factor))
        found = carried
    return sorted(found, key=lambda r: -r.value.real)


#: Memoised: the classifier's linear-theory check and the certificate both ask it of a
#: run at rest, and past the gate it carries every root by Newton.
@lru_cache(maxsize=64)
def rest_exponent(p: Params) -> float:
    """The real part of the leading nonzero root at the rest state of p (with its noise d):
    its growth rate of small perturbations. Negative: stable; positive: a window that sits
    there will leave it; within NEUTRAL_TOL of 0: undecided.

    Computed only near or past the Hopf curve: below STABLE_GATE k_H(tau) (F' > 0, d up to
    GATE_MAX_D) it returns -inf (stable, rate not computed). Raises ArithmeticError when a
    root cannot be carried to the noisy state. A positive result is sound (Newton stopped
    on a root); for large d a root that no noise-free one leads to would be missed.
    """
    if p.F1 > 0.0 and p.tau > 0.0 and p.d <= GATE_MAX_D and p.k < STABLE_GATE * hopf_k(p.tau, p.F1):
        return -math.inf
    if p.d == 0.0:
        return leading_exponent(p)
    # imported here, past the gate: core.hopf_start brings the orbit kernels (core.orbit)
    from core.hopf_start import jacobians, steady_state
    from core.orbit import OrbitError
    try:
        ss = steady_state(p)
    except OrbitError as exc:
        raise ArithmeticError(str(exc)) from None
    j0, jt = jacobians(p, ss)
    start = [*roots(p.F1, p.k, p.tau), *variance_roots(p)]
    best = -math.inf
    for lam in _nonzero(np.array(start, dtype=complex)):
        if abs(lam.imag) < 1e-12:   # keep Newton off the real axis's double roots
            lam = complex(lam.real, 1e-9)
        carried = _carry(complex(lam), j0, jt, p.tau)
        if carried is None:
            raise ArithmeticError(f"the root {complex(lam):.6g} of the noise-free state could not "
                                  f"be carried to the noisy one (d = {p.d:g})")
        best = max(best, carried.real)
    return float(best)


def _nonzero(r: np.ndarray) -> np.ndarray:
    """The roots away from 0 (the m_x shift's root, and the variance block's at k = 0)."""
    return r[np.abs(r) > 1e-9]
