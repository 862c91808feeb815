"""Linear stability of the sliding state (the fixed point of eq. 18), and the Hopf boundary.

Linearising eqs. 6a-6e at m_y = s_x = s_y = u = 0 (d = 0), the characteristic function
factorises as -(lam + F') (lam^2 + 2 F' lam + 4k) * h(lam) with

    h(lam) = lam^2 + F' lam + k (1 - exp(-lam tau)),           F' = F'(v)   (eq. 20)

Only h has the delay; the variance block (6c-6e) is stable whenever F' > 0. lam = 0 is
always a root of h: shifting m_x by a constant changes nothing. The *leading nonzero root*
of h decides stability, and it is what lambda_max equals in the sliding regime.

Hopf boundary (lam = i omega in h): omega^2 = 2k - F'^2 and
    cos(omega tau) = (F'^2 - k) / k,   sin(omega tau) = -F' omega / k,
so along omega in (0, inf) the first branch is
    k_H = (omega^2 + F'^2) / 2,  tau_H = [atan2(-F' omega, F'^2 - k_H) mod 2 pi] / omega.
tau_H falls monotonically from inf (k -> F'^2/2) to 0 (k -> pi^2 / (2 tau^2)).
For k < F'^2/2 the sliding state is stable for every tau.

The same two equations hold on every later root crossing: the n-th Hopf branch adds
2 pi (n - 1) to omega tau,
    tau_n(omega) = [atan2(-F' omega, F'^2 - k) mod 2 pi + 2 pi (n - 1)] / omega,
so at one tau the n-th pair of roots crosses at k_n > k_{n-1}, with omega_n tau in
((2n - 1) pi, 2 n pi): the n-th oscillation has a period in (tau / n, tau / (n - 1/2)).
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from core.params import Params

TWO_PI = 2.0 * math.pi


def characteristic(lam: complex, f1: float, k: float, tau: float) -> complex:
    """h(lam) = lam^2 + F' lam + k (1 - e^{-lam tau})."""
    return lam * lam + f1 * lam + k * (1.0 - np.exp(-lam * tau))


def _characteristic_slope(lam: complex, f1: float, k: float, tau: float) -> complex:
    return 2.0 * lam + f1 + k * tau * np.exp(-lam * tau)


def _newton(lam: complex, f1: float, k: float, tau: float, steps: int = 50) -> complex:
    for _ in range(steps):
        step = characteristic(lam, f1, k, tau) / _characteristic_slope(lam, f1, k, tau)
        lam -= step
        if abs(step) < 1e-15 * max(1.0, abs(lam)):
            break
    return lam


def _generator_eigenvalues(f1: float, k: float, tau: float, m: int) -> np.ndarray:
    """Rightmost roots of h, approximated by the eigenvalues of the infinitesimal generator
    of z' = A0 z + A1 z(t - tau), z = (m_x, m_y), discretised by Chebyshev collocation on
    [-tau, 0] with m + 1 nodes (Breda, Maset & Vermiglio, SIAM J. Sci. Comput. 2005)."""
    j = np.arange(m + 1)
    x = np.cos(np.pi * j / m)                       # Chebyshev points on [-1, 1], x_0 = 1
    cw = np.where((j == 0) | (j == m), 2.0, 1.0) * (-1.0) ** j
    dx = x[:, None] - x[None, :]
    dmat = np.outer(cw, 1.0 / cw) / (dx + np.eye(m + 1))
    dmat -= np.diag(dmat.sum(axis=1))
    dmat *= 2.0 / tau                                # theta = tau (x - 1) / 2
    a0 = np.array([[0.0, 1.0], [-k, -f1]])
    a1 = np.array([[0.0, 0.0], [k, 0.0]])
    big = np.kron(dmat, np.eye(2))
    big[0:2, :] = 0.0
    big[0:2, 0:2] = a0                               # node 0: theta = 0
    big[0:2, 2 * m:2 * m + 2] = a1                   # node m: theta = -tau
    return np.linalg.eigvals(big)


def roots(f1: float, k: float, tau: float, count: int = 6) -> np.ndarray:
    """The ``count`` rightmost roots of h with Im >= 0, refined by Newton, best first.

    The zero root is included when present. Accurate to ~1e-12 for the rightmost roots.
    """
    if tau == 0.0 or k == 0.0:
        r = np.roots([1.0, f1, 0.0]).astype(complex)
        return r[np.argsort(-r.real)][:count]
    m = int(min(200, max(24, 4.0 * tau * math.sqrt(max(k, 1.0)) + 24)))
    cand = _generator_eigenvalues(f1, k, tau, m)
    cand = cand[cand.imag >= -1e-9]
    cand = cand[np.argsort(-cand.real)][: 3 * count]
    refined = []
    for lam in cand:
        r = _newton(complex(lam), f1, k, tau)
        if abs(characteristic(r, f1, k, tau)) > 1e-8 * max(1.0, abs(r) ** 2):
            continue
        r = complex(r.real, abs(r.imag))
        if all(abs(r - s) > 1e-8 * max(1.0, abs(r)) for s in refined):
            refined.append(r)
    out = np.array(refined, dtype=complex)
    return out[np.argsort(-out.real)][:count]


def leading_root(p: Params) -> complex:
    """The leading *nonzero* root of h at the point p (Im >= 0).

    Its real part is the growth rate of small perturbations of the sliding state,
    so lambda_max of a sliding run must equal it.
    """
    for r in roots(p.F1, p.k, p.tau):
        if abs(r) > 1e-9:
            return r
    raise ArithmeticError("no nonzero root found")  # pragma: no cover - h always has one


def variance_roots(p: Params) -> np.ndarray:
    """Roots of the delay-free factors -(lam + F') (lam^2 + 2 F' lam + 4k): the variance
    block (6c-6e) linearised at the sliding state."""
    quad = np.roots([1.0, 2.0 * p.F1, 4.0 * p.k]).astype(complex)
    return np.concatenate(([complex(-p.F1)], quad))


#: Memoised: a run's analysis asks it of one Params up to three times (the classifier's
#: linear-transient reading, its linear-theory check and the certificate), ~20 ms each.
@lru_cache(maxsize=64)
def leading_exponent(p: Params) -> float:
    """Real part of the leading nonzero root of the *full* characteristic function.

    This is what lambda_max of a sliding run converges to. Usually the delay factor h
    leads, but for small tau its roots move far left and the variance block's -F'
    (e.g. -3.456 at the defaults with tau = 0.2, k = 12, where h's leading root is -10.35)
    takes over.
    """
    var = variance_roots(p)
    var = var[np.abs(var) > 1e-12]      # k = 0 gives the variance block a zero root too
    return max([leading_root(p).real, *var.real.tolist()])


def check_branch(branch: int) -> int:
    """The Hopf branch index n, checked: a whole number >= 1."""
    if isinstance(branch, bool) or not isinstance(branch, int) or branch < 1:
        raise ValueError(f"the Hopf branch index must be a whole number >= 1, not {branch!r}")
    return branch


def hopf_k(tau: float, f1: float, branch: int = 1) -> float:
    """k_n(tau): the critical stiffness on the n-th Hopf branch (n = ``branch``; the first,
    the stability boundary, by default), for F' = f1 > 0.

    Solves tau_n(omega) = tau for omega by bisection on log(omega) (tau_n is monotone).
    Returns +inf for tau = 0 (no delay: stable for every k).
    """
    check_branch(branch)
    if f1 <= 0.0:
        raise ValueError("the Hopf curve in k needs F'(v) > 0 (a damped sliding state)")
    if tau <= 0.0:
        return math.inf
    lo, hi = 1e-9, 1e9
    for _ in range(200):
        mid = math.sqrt(lo * hi)
        if hopf_tau(mid, f1, branch=branch) > tau:
            lo = mid
        else:
            hi = mid
        if hi / lo < 1.0 + 1e-15:
            break
    omega = math.sqrt(lo * hi)
    return 0.5 * (omega * omega + f1 * f1)


def hopf_period(tau: float, f1: float) -> float:
    """2 pi / omega_H: the period of the oscillation born on the first Hopf branch at this
    tau and F'; NaN where there is none (F' <= 0 or tau = 0). It lies in (tau, 2 tau)
    (omega tau is in (pi, 2 pi) on that branch) and is the *basic period* core.classify
    counts return times in.

    Measured against the return times of settled orbits far from the curve (RK4,
    dt = 0.01, t_end = 2e4): k = 15, tau = 10: 10.419 / 10.573 = 0.985; k = 6, b = 15.5,
    tau = 21.3 (a square wave): 22.82 / 22.40 = 1.019; k = 30, tau = 1: 1.307 / 1.409 =
    0.928; k = 6, tau = 60: 60.58 / 60.58 = 1.000.
    """
    if f1 <= 0.0 or tau <= 0.0:
        return math.nan
    k_h = hopf_k(tau, f1)
    return TWO_PI / math.sqrt(2.0 * k_h - f1 * f1)


def hopf_tau(omega: float, f1: float, k: float | None = None, branch: int = 1) -> float:
    """tau on the n-th Hopf branch (n = ``branch``) at frequency omega (k = (omega^2 +
    F'^2)/2 by default): omega tau is the first crossing's angle plus 2 pi (n - 1)."""
    if k is None:
        k = 0.5 * (omega * omega + f1 * f1)
    return (math.atan2(-f1 * omega, f1 * f1 - k) % TWO_PI + TWO_PI * (branch - 1)) / omega


def hopf_omega(tau: float, f1: float, branch: int = 1) -> float:
    """omega_n: the angular frequency of the n-th Hopf branch at this tau (the roots
    +-i omega_n of h at k = k_n(tau)); NaN where there is none (F' <= 0 or tau = 0)."""
    if f1 <= 0.0 or tau <= 0.0:
        return math.nan
    return math.sqrt(2.0 * hopf_k(tau, f1, branch) - f1 * f1)


def hopf_curve_k_tau(p: Params, taus: np.ndarray) -> np.ndarray:
    """k_H at each tau in the (k, tau) plane, other parameters from p."""
    return np.array([hopf_k(float(t), p.F1) for t in taus])


def hopf_curve_friction(p: Params, name: str, n: int = 400) -> tuple[np.ndarray, np.ndarray]:
    """The Hopf boundary in the (name, tau) plane for name in a, b, c, at the k of p.

    For fixed k the boundary needs F'_H = sqrt(2k - omega^2), omega in (0, sqrt(2k));
    then F'(v) = F'_H is solved for the friction parameter (it enters F' linearly).
    Returns (values of the parameter, tau), ordered by tau. The sliding state is stable on
    the side where F' > F'_H, i.e. larger a or c, smaller b.
    """
    if p.k <= 0.0:
        raise ValueError("the Hopf curve needs k > 0")
    omega = math.sqrt(2.0 * p.k) * np.sin(np.linspace(1e-4, 0.5 * math.pi * (1 - 1e-4), n)) ** 2
    f1_h = np.sqrt(2.0 * p.k - omega * omega)
    tau = np.array([hopf_tau(w, f, p.k) for w, f in zip(omega, f1_h, strict=True)])
    val = np.asarray(friction_for_slope(p, name, f1_h))
    order = np.argsort(tau)
    return val[order], tau[order]


def friction_for_slope(p: Params, name: str, f1: np.ndarray | float) -> np.ndarray | float:
    """The value of friction parameter ``name`` (a, b or c) that gives F'(v) = f1, the
    others from p (F' = 3 a v^2 - 2 b v + c, eq. 10: linear in each)."""
    v = p.v
    if name == "a":
        return (f1 + 2.0 * p.b * v - p.c) / (3.0 * v * v)
    if name == "b":
        return (3.0 * p.a * v * v + p.c - f1) / (2.0 * v)
    if name == "c":
        return f1 - 3.0 * p.a * v * v + 2.0 * p.b * v
    raise ValueError(f"no Hopf curve in the ({name}, tau) plane: name must be a, b or c")


def hopf_friction(p: Params, name: str, branch: int = 1) -> tuple[float, float]:
    """The friction parameter ``name`` (a, b or c) on the n-th Hopf curve (n = ``branch``)
    at p's k and tau, and the angular frequency omega there: for n = 1 one point of
    hopf_curve_friction. Along that curve
    tau falls as omega rises from 0 to sqrt(2k), so omega is found by bisection. Raises ValueError when no F' > 0 puts
    (k, tau) on the curve (k <= 0, or tau below the curve's reach pi / sqrt(2k))."""
    check_branch(branch)
    if p.k <= 0.0 or p.tau <= 0.0:
        raise ValueError("the Hopf curve in a friction parameter needs k > 0 and tau > 0")
    top = math.sqrt(2.0 * p.k)

    def tau_at(w: float) -> float:
        return hopf_tau(w, math.sqrt(max(2.0 * p.k - w * w, 0.0)), p.k, branch)

    lo, hi = top * 1e-9, top * (1.0 - 1e-12)
    if not tau_at(hi) < p.tau < tau_at(lo):
        raise ValueError(f"no Hopf point in {name} at k = {p.k:g}, tau = {p.tau:g}")
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if tau_at(mid) > p.tau:
            lo = mid
        else:
            hi = mid
        if hi - lo < 1e-15 * top:
            break
    w = 0.5 * (lo + hi)
    return float(friction_for_slope(p, name, math.sqrt(2.0 * p.k - w * w))), w


def small_tau_k(tau: float | np.ndarray, f1: float) -> float | np.ndarray:
    """The paper's small-tau approximation of the boundary, eq. 26 (from eq. 25).

    Only qualitative: its leading term 0.76 / tau^2 is ~6.5 times below the exact
    pi^2 / (2 tau^2), because eq. 21 truncates the delay expansion at O(tau^3).
    """
    r6 = math.sqrt(6.0)
    tau = np.asarray(tau, dtype=float)
    return (4 * r6 - 6) / (5 * tau**2) - (4 - r6) * f1 / (5 * tau) + f1 * f1 / (4 * r6)


def paper_fit_k(tau: float | np.ndarray) -> float | np.ndarray:
    """The paper's fit of its numerical sliding/oscillatory boundary, eq. 27.

    NaN outside 0.1 < tau < 5, where the paper gives no fit.
    """
    tau = np.asarray(tau, dtype=float)
    low = 4.56 / tau**2 + 8.5 / tau + 1.6
    high = 5.4 / tau**2 + 5.2 / tau + 5.19
    return np.where((tau > 0.1) & (tau < 0.5), low, np.where((tau >= 0.5) & (tau < 5.0), high, np.nan))

