"""The Hopf point of the steady sliding state, with noise, and the small orbit born there.

core.stability gives the exact Hopf curve of the noise-free fixed point (eq. 18: d = 0,
where the characteristic function factorises). With noise d > 0 the steady state slides
at a small constant m_y = y* with s_y* = s_x* k > 0 and u* = 0 (eqs. 6b-6e with
m_x(t) - m_x(t - tau) = tau y*), and the variance block couples to the delay block: the
Hopf point moves (at tau = 10, d = 1e-4: k_H = 6.14619 against 6.14854 without noise,
found both here and at the end of the cycle branch by continuation). This module
linearises eqs. 6a-6e at that state (core.model.rhs_tangent), solves
det(i w I - J_0 - J_tau e^{-i w tau}) = 0 for the parameter and w by Newton's method from
the noise-free point, and builds the orbit of small amplitude eps along the critical
eigenvector: the start of a continuation from the Hopf point. The n-th Hopf point (the
n-th pair of roots on the axis, core.stability's n-th branch) starts Newton from the
noise-free n-th point instead; its orbits are a branch of their own.
"""

from __future__ import annotations

import contextlib
import math
from dataclasses import dataclass

import numpy as np

from core.model import rhs_tangent
from core.orbit import Grid, OrbitError
from core.params import Params
from core.stability import check_branch, hopf_friction, hopf_k, hopf_tau

#: Newton's tolerance on |det| (scaled) for the Hopf point, and its step budget. Newton
#: also stops once its step is below HOPF_STEP_TOL relative: in b at k = 12, tau = 10
#: (b_H = 0.17) |det| stalls at ~1e-11 from rounding, with steps of 1e-17.
HOPF_TOL, HOPF_STEPS = 1e-13, 50
HOPF_STEP_TOL = 1e-13


@dataclass(frozen=True)
class SteadyState:
    """The steady sliding state: m_y = y (a constant drift), s_x, s_y, u = 0."""

    y: float
    s_x: float
    s_y: float


def steady_state(p: Params) -> SteadyState:
    """Solve eq. 6b (with the delay term -k tau y) and eq. 6d (u = 0) for (y, s_y)."""
    y, s = 0.0, (p.d / p.F1 if p.F1 > 0 else 0.0)
    for _ in range(100):
        g = p.F1 + 2 * p.q * y + 3 * p.a * (y * y + s)
        e1 = -y * (p.F1 + y * (p.q + p.a * y)) - s * (p.q + 3 * p.a * y) - p.k * p.tau * y
        e2 = -2 * s * g + 2 * p.d
        j11 = -(p.F1 + 2 * p.q * y + 3 * p.a * y * y) - 3 * p.a * s - p.k * p.tau
        j12 = -(p.q + 3 * p.a * y)
        j21 = -2 * s * (2 * p.q + 6 * p.a * y)
        j22 = -2 * g - 6 * p.a * s
        det = j11 * j22 - j12 * j21
        if det == 0.0:
            break
        dy = (-e1 * j22 + e2 * j12) / det
        ds = (-j11 * e2 + j21 * e1) / det
        y, s = y + dy, s + ds
        if abs(dy) + abs(ds) < 1e-15:
            return SteadyState(y, s / p.k if p.k > 0 else 0.0, s)
    raise OrbitError("no steady sliding state near the fixed point at these parameters")


def jacobians(p: Params, ss: SteadyState) -> tuple[np.ndarray, np.ndarray]:
    """J_0 (the current state) and J_tau (the delayed m_x) of eqs. 6a-6e at the steady
    state, columns from core.model.rhs_tangent."""
    j0 = np.empty((5, 5))
    for i in range(5):
        e = np.zeros(5)
        e[i] = 1.0
        j0[:, i] = rhs_tangent(ss.y, ss.s_y, 0.0, *e, 0.0, p.a, p.q, p.F1, p.k)
    jt = np.zeros((5, 5))
    jt[:, 0] = rhs_tangent(ss.y, ss.s_y, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, p.a, p.q, p.F1, p.k)
    return j0, jt


def _char(p: Params, w: float) -> tuple[complex, np.ndarray]:
    """det(i w I - J_0 - J_tau e^{-i w tau}) / (i w) (the zero root divided out) and the
    matrix."""
    j0, jt = jacobians(p, steady_state(p))
    a = 1j * w * np.eye(5) - j0 - jt * np.exp(-1j * w * p.tau)
    return complex(np.linalg.det(a)) / (1j * w), a


@dataclass(frozen=True)
class HopfPoint:
    """The Hopf point in ``name``: its value, angular frequency, steady state, and the
    critical eigenvector (components m_x, m_y, s_x, s_y, u; m_x's set to 1)."""

    name: str
    value: float
    omega: float
    steady: SteadyState
    vector: np.ndarray
    #: Which root crossing: 1 the first (the stability boundary), n the n-th pair.
    branch: int = 1

    @property
    def period(self) -> float:
        return 2 * math.pi / self.omega


def hopf_point(p: Params, name: str = "k", branch: int = 1) -> HopfPoint:
    """The n-th Hopf point (n = ``branch``) of the noisy steady state in parameter
    ``name``, starting from the noise-free n-th Hopf point (core.stability) when the
    parameter is k, a, b or c (and tau for n > 1), else from p itself (n = 1 only)."""
    check_branch(branch)
    if p.tau <= 0.0:
        raise OrbitError("tau must be > 0: there is no Hopf point without a delay")
    value = getattr(p, name)
    w = 2 * math.pi / (p.tau + 1)
    if name == "k" and p.F1 > 0:
        value = hopf_k(p.tau, p.F1, branch)
        w = math.sqrt(max(2 * value - p.F1 ** 2, 1e-6))
    elif name in ("a", "b", "c"):
        with contextlib.suppress(ValueError):  # none in reach: Newton from p itself
            value, w = hopf_friction(p, name, branch)
    elif branch > 1 and name == "tau" and 2 * p.k > p.F1 ** 2 > 0:
        # every branch crosses at the same omega = sqrt(2k - F'^2) in tau (k fixed)
        w = math.sqrt(2 * p.k - p.F1 ** 2)
        value = hopf_tau(w, p.F1, p.k, branch)
    elif branch > 1:
        raise OrbitError(f"the Hopf point of branch {branch} is found in k, tau, a, b or c "
                         f"(from the noise-free one), not in {name}")
    x = np.array([value, w])
    for _ in range(HOPF_STEPS):
        q = p.with_(**{name: float(x[0])})
        f, _ = _char(q, float(x[1]))
        if abs(f) < HOPF_TOL * max(1.0, abs(x[0]) ** 2):
            break
        jac = np.empty((2, 2))
        for i, h in enumerate((1e-7 * max(1.0, abs(x[0])), 1e-7 * max(1.0, abs(x[1])))):
            xh = x.copy()
            xh[i] += h
            fh, _ = _char(p.with_(**{name: float(xh[0])}), float(xh[1]))
            jac[:, i] = [(fh - f).real / h, (fh - f).imag / h]
        step = np.linalg.solve(jac, [-f.real, -f.imag])
        x = x + step
        if np.all(np.abs(step) <= HOPF_STEP_TOL * np.maximum(1.0, np.abs(x))):
            break
    else:
        raise OrbitError(f"no Hopf point in {name} near {getattr(p, name):g}")
    q = p.with_(**{name: float(x[0])})
    _, a = _char(q, float(x[1]))
    _, _, vh = np.linalg.svd(a)
    v = vh[-1].conj()
    v = v / v[0]
    return HopfPoint(name, float(x[0]), abs(float(x[1])), steady_state(q), v, branch)


def small_orbit(h: HopfPoint, g: Grid, eps: float) -> tuple[np.ndarray, np.ndarray]:
    """(reduced state, its derivative in eps) of the orbit of amplitude eps (in m_x) at
    the Hopf point, on the section where the mode's phase is 0."""
    n = g.n_delay
    s = np.arange(1, n + 1) * g.dt
    v = h.vector
    ss = h.steady
    mode_now = v[1:].real
    xi = (v[0] * (np.exp(-1j * h.omega * s) - 1.0)).real
    eta = (v[1] * np.exp(-1j * h.omega * s)).real
    base = np.concatenate(([ss.y, ss.s_x, ss.s_y, 0.0], -ss.y * s, np.full(n, ss.y)))
    direction = np.concatenate((mode_now, xi, eta))
    return base + eps * direction, direction
