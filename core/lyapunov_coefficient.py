"""The first Lyapunov coefficient l1 of a Hopf point, and the Bautin point where it vanishes.

On the centre manifold of a Hopf point the flow has the normal form (Kuznetsov, Elements of
Applied Bifurcation Theory, eq. 3.18)

    w' = lambda(p) w + c1 |w|^2 w + O(|w|^4),    x = x* + w q + conj(w q) + O(|w|^2),

with |q| = 1 (the Euclidean norm over m_x, m_y, s_x, s_y, u) and l1 = Re c1 / omega. Its sign
is the criticality: l1 < 0 supercritical (the small orbits are stable and exist where the
steady state is unstable), l1 > 0 subcritical. The small orbit of radius r = |w| exists where
Re lambda(p) + Re c1 r^2 = 0, so along the branch from the Hopf point

    p - p_H = alpha r^2 + beta r^4 + ...,     l1 = -Re lambda'(p_H) alpha / omega.

This module measures exactly that: it corrects the orbits of several small amplitudes on the
branch (core.continuation.Branch.from_hopf: shooting, the parameter free), reads r^2 off each
as the power of its first harmonic (sum over the five variables of |a_j|^2, a_j the first
Fourier coefficient, m_x's drift removed: a_j = r q_j up to a phase and O(r^3)), fits
p(r^2) by least squares with p_H free (the discrete map's own Hopf point, ~1e-9 from the
continuous one), and divides by dlambda/dp from the characteristic matrix of the noisy
steady state (core.hopf_start). The normal form's zero eigenvalue (a shift of m_x) is a
symmetry and drops out of this reading, where the textbook formula for c1 would have to
solve with the singular Delta(0).

Checked: the sign against the branches' stability on either side of the switch of
criticality (tau = 0.6 supercritical, tau = 0.7 subcritical in k); l1 and the Bautin point
against DDE-BIFTOOL's normal form (benchmarks/ddebiftool; its stock nmfm_hopf divides by the
singular Delta(0) too, so the harness solves the frequency-0 terms around the drift): l1 to
5e-6 for tau <= 10, the Bautin point to 2.4e-6 in k and 1.9e-6 in tau.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator
from dataclasses import dataclass

import numpy as np

from core.continuation import Branch
from core.hopf_start import HopfPoint, jacobians, steady_state
from core.orbit import Shot
from core.params import Params

#: The orbits' amplitudes (of m_x along the critical eigenvector, core.hopf_start's
#: small_orbit). Measured against DDE-BIFTOOL's normal form with exact multilinear forms
#: (benchmarks/ddebiftool, Kuznetsov's normalisation as here): l1 within 5e-6 absolute and
#: 2.3e-4 relative at tau = 0.5 to 10 on the first Hopf curve (1e-5 to 3e-5 relative but
#: next to the Bautin point, where l1 is 0.02), 1e-3 relative at tau = 20. At tau = 10 twice these
#: amplitudes moved l1 by 1.3e-3 (the fit's r^6 remainder) and half of them by 2.6e-3 (Newton's
#: tolerance over the smaller p - p_H).
AMPLITUDES = (0.0025, 0.005, 0.0075, 0.01)
#: The relative step of the finite differences of the characteristic determinant.
CHAR_STEP = 1e-6


@dataclass(frozen=True)
class Lyapunov:
    """l1 at a Hopf point, with what it was read from: the Hopf point (parameter value,
    omega), Re dlambda/dp there, the fitted alpha = dp/d(r^2) and the fit's residual."""

    name: str
    value: float
    omega: float
    l1: float
    root_speed: float
    alpha: float
    residual: float

    @property
    def criticality(self) -> str:
        return "supercritical" if self.l1 < 0 else "subcritical"


def characteristic_det(p: Params, lam: complex) -> complex:
    """det(lam I - J_0 - J_tau e^{-lam tau}) at p's noisy steady state."""
    j0, jt = jacobians(p, steady_state(p))
    return complex(np.linalg.det(lam * np.eye(5) - j0 - jt * np.exp(-lam * p.tau)))


def root_speed(hopf: HopfPoint, p: Params) -> complex:
    """dlambda/dp of the critical root at the Hopf point: -D_p / D_lambda (implicit
    differentiation of D(lambda, p) = 0, both by central differences)."""
    q = p.with_(**{hopf.name: hopf.value})
    lam = 1j * hopf.omega
    h = CHAR_STEP * max(1.0, hopf.omega)
    d_lam = (characteristic_det(q, lam + h) - characteristic_det(q, lam - h)) / (2 * h)
    hp = CHAR_STEP * max(1.0, abs(hopf.value))
    d_p = (characteristic_det(q.with_(**{hopf.name: hopf.value + hp}), lam)
           - characteristic_det(q.with_(**{hopf.name: hopf.value - hp}), lam)) / (2 * hp)
    return -d_p / d_lam


def first_harmonic_power(shot: Shot, n_delay: int, dt: float, period: float) -> float:
    """sum_j |a_j|^2 over the five variables, a_j = (1/T) int_0^T x_j(t) e^{-i w t} dt
    (w = 2 pi / T), by the trapezoid rule on the shot's steps and its last partial step;
    m_x's drift over the period is removed first (m_x is periodic up to it)."""
    col, w = shot.col, shot.w
    traj = shot.traj[:, n_delay:col]                   # t = 0, dt, ..., (m - 1) dt
    end = shot.traj[:, col - 1:col + 3] @ w             # t = T
    m = traj.shape[1]
    t = np.arange(m) * dt
    t_all = np.concatenate((t, [period]))
    x = np.concatenate((traj, end[:, None]), axis=1)
    x[0] -= (x[0, -1] - x[0, 0]) * t_all / period
    kernel = np.exp(-2j * math.pi * t_all / period)
    a = np.trapezoid(x * kernel, t_all, axis=1) / period
    return float(np.sum(np.abs(a) ** 2))


def first_lyapunov(p: Params, name: str = "k", dt: float = 0.01, hopf_branch: int = 1,
                   amplitudes: Iterable[float] = AMPLITUDES) -> Lyapunov:
    """l1 at the ``hopf_branch``-th Hopf point in ``name`` at p (see the module doc)."""
    values, powers = [], []
    hopf = None
    for eps in amplitudes:
        branch, hopf = Branch.from_hopf(p, name, dt, eps, eps, eps, hopf_branch)
        n = branch.g0.size
        values.append(float(branch.y[-1]))
        powers.append(first_harmonic_power(branch.shot, branch.g0.n_delay,
                                           branch.map_at(values[-1]).g.dt,
                                           float(branch.y[n])))
    assert hopf is not None, "at least one amplitude"
    r2 = np.array(powers)
    design = np.column_stack((np.ones_like(r2), r2, r2 * r2))
    coef, *_ = np.linalg.lstsq(design, np.array(values), rcond=None)
    fitted = design @ coef
    residual = float(np.max(np.abs(fitted - values))) if len(values) > 3 else math.nan
    speed = root_speed(hopf, p).real
    alpha = float(coef[1])
    return Lyapunov(name, hopf.value, hopf.omega, -speed * alpha / hopf.omega, speed,
                    alpha, residual)


@dataclass(frozen=True)
class HopfCurvePoint:
    """The Hopf point in ``first`` at one value of ``second``, with its l1."""

    first: float
    second: float
    period: float
    l1: float


def hopf_curve(p: Params, names: tuple[str, str], values: Iterable[float], dt: float = 0.01,
               hopf_branch: int = 1) -> Iterator[HopfCurvePoint]:
    """The Hopf curve: the Hopf point in names[0] at each value of names[1], with l1."""
    for value in values:
        ly = first_lyapunov(p.with_(**{names[1]: value}), names[0], dt, hopf_branch)
        yield HopfCurvePoint(ly.value, value, 2 * math.pi / ly.omega, ly.l1)


def bautin(p: Params, names: tuple[str, str], a: HopfCurvePoint, b: HopfCurvePoint,
           dt: float = 0.01, hopf_branch: int = 1, tol: float = 1e-7
           ) -> HopfCurvePoint:
    """The Bautin point between two Hopf-curve points whose l1 differ in sign: l1 = 0 by
    the secant method in names[1] (Illinois safeguard), to ``tol`` relative."""
    lo, hi = a, b
    f_lo, f_hi = lo.l1, hi.l1
    point, previous, side = a, math.inf, 0
    for _ in range(40):
        s = lo.second - f_lo * (hi.second - lo.second) / (f_hi - f_lo)
        point = next(hopf_curve(p, names, [s], dt, hopf_branch))
        if abs(s - previous) < tol * max(1.0, abs(s)) or point.l1 == 0.0:
            return point
        previous = s
        if point.l1 * f_lo > 0:
            lo, f_lo = point, point.l1
            if side == -1:
                f_hi /= 2  # Illinois: the same side twice halves the other end's weight
            side = -1
        else:
            hi, f_hi = point, point.l1
            if side == 1:
                f_lo /= 2
            side = 1
    return point


__all__ = [
    "HopfCurvePoint",
    "Lyapunov",
    "bautin",
    "first_harmonic_power",
    "first_lyapunov",
    "hopf_curve",
    "root_speed",
]
