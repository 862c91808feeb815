"""Labels follow linear theory: a window that still sits at a rest state
whose leading root is positive is not sliding at a fixed point. Checked against theory (the
exact Hopf formula, roots found here by scipy on the characteristic function), never
against the tool's earlier labels.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import fsolve

from core.classify import classify
from core.heading import heading
from core.hopf_start import hopf_point, jacobians, steady_state
from core.params import Params
from core.point import run_point
from core.rest_stability import NEUTRAL_TOL, rest_exponent
from core.solve import SolverSettings
from core.stability import hopf_k, leading_root

T = np.arange(0.0, 1000.0, 0.01)


def rest_window(level: float = 1e-6) -> np.ndarray:
    """A window at rest at the fixed point (m_y constant, m_x drifting with it)."""
    w = np.zeros((5, len(T)))
    w[0] = level * T
    w[1] = level
    return w


def scipy_leading_root(f, omegas: np.ndarray) -> complex:
    """The rightmost of the roots of the analytic f that scipy's hybrid method on (Re, Im)
    reaches from the points i omega (tau = 60 has several roots near the imaginary axis:
    at k = 6 two have crossed it, at omega ~ 0.104 and ~ 0.207)."""
    def parts(x):
        v = f(complex(x[0], x[1]))
        return [v.real, v.imag]
    found = []
    for w in omegas:
        x, info, ok, _ = fsolve(parts, [0.0, w], xtol=1e-13, full_output=True)
        # ok 3: no further improvement at this xtol, i.e. converged to round-off
        if ok in (1, 3) and np.hypot(*info["fvec"]) < 1e-10 and x[1] > 1e-6:
            found.append(complex(x[0], x[1]))
    assert found
    return max(found, key=lambda r: r.real)


def test_the_conclusions_point_has_a_positive_leading_root_by_scipy_too():
    # h(lam) = lam^2 + F' lam + k (1 - e^{-lam tau}) at tau = 60, noise-free: +1.29e-7
    # (the issue's +1.3e-7)
    p = Params(k=6.0, tau=60.0, d=0.0)
    ref = scipy_leading_root(lambda lam: lam * lam + p.F1 * lam + p.k * (1 - np.exp(-lam * p.tau)),
                             np.linspace(0.05, 1.0, 20))
    assert ref.real == pytest.approx(1.2857e-7, rel=1e-3)
    assert leading_root(p) == pytest.approx(ref, abs=1e-12)
    assert rest_exponent(p) == pytest.approx(ref.real, abs=1e-13)


def test_the_noisy_rest_state_root_by_scipy_on_the_full_determinant():
    # with the default noise the rest state is the drifting steady state; its leading root
    # solves det(lam I - J_0 - J_tau e^{-lam tau}) = 0
    p = Params(k=6.0, tau=60.0)
    j0, jt = jacobians(p, steady_state(p))

    def det(lam: complex) -> complex:
        return complex(np.linalg.det(lam * np.eye(5) - j0 - jt * np.exp(-lam * p.tau))) / lam

    ref = scipy_leading_root(det, np.linspace(0.05, 1.0, 20))
    assert ref.real > 1e-7
    assert rest_exponent(p) == pytest.approx(ref.real, rel=1e-6)


@pytest.mark.parametrize("tau", [0.8, 2.0, 10.0, 60.0])
def test_the_root_changes_sign_at_the_hopf_point_and_is_numerically_zero_there(tau):
    base = Params(tau=tau)
    k_h = hopf_point(base, "k").value            # the noisy rest state's Hopf point
    assert abs(rest_exponent(base.with_(k=k_h))) <= NEUTRAL_TOL / 100
    assert rest_exponent(base.with_(k=k_h * (1 + 1e-4))) > NEUTRAL_TOL
    assert rest_exponent(base.with_(k=k_h * (1 - 1e-4))) < -NEUTRAL_TOL
    k0 = hopf_k(tau, base.F1)                     # the exact formula, without noise
    assert abs(rest_exponent(base.with_(k=k0, d=0.0))) <= NEUTRAL_TOL / 100


def test_a_rest_state_on_the_hopf_curve_decides_nothing_and_says_so():
    p = Params(k=hopf_k(10.0, Params().F1), tau=10.0, d=0.0, delta=1e-6)
    s = classify(T, rest_window(), p=p)
    assert (s.regime, s.attractor) == ("sliding", "fixed-point"), s
    assert "linear theory decides nothing" in s.detail and "not-departed" not in s.flags


@pytest.mark.parametrize("tau", [10.0, 60.0])
def test_below_the_hopf_curve_a_rest_window_stays_sliding(tau):
    p = Params(k=0.99 * hopf_k(tau, Params().F1), tau=tau, delta=1e-6)
    s = classify(T, rest_window(), p=p)
    assert (s.regime, s.attractor, s.flags, s.detail) == ("sliding", "fixed-point", (), "at rest")


@pytest.mark.slow  # 1-3 s: a short branch walk
def test_past_a_supercritical_hopf_point_a_rest_window_is_headed_for_the_small_cycle():
    # tau = 0.5: supercritical (the Bautin point lies near tau = 0.65, numerics.md); one
    # per cent past k_H the branch's small orbit is stable
    p = Params(k=1.01 * hopf_k(0.5, Params().F1), tau=0.5, delta=1e-6)
    s = classify(T, rest_window(), p=p)
    assert (s.regime, s.attractor) == ("oscillatory", "unstable-fixed-point"), s
    assert "not-departed" in s.flags and not s.settled
    assert "supercritical" in s.detail and "stable cycle" in s.detail


def test_where_no_hopf_branch_exists_the_regime_is_undetermined_with_the_reason():
    # b = 30: F'(v) = -1.10 < 0, the variance block's root -F' > 0 for every k and tau
    p = Params(b=30.0, k=6.0, tau=10.0, delta=1e-6)
    s = classify(T, rest_window(), p=p)
    assert (s.regime, s.attractor) == ("undetermined", "unstable-fixed-point"), s
    assert "not-departed" in s.flags and "F'(v) = -1.104 <= 0" in s.detail


def test_a_cycle_beside_a_stable_rest_state_is_kept():
    # bistability: at tau = 10, k = 5.5 < k_H the rest state is stable, and a cycle
    # coexists (the Hopf point is subcritical): theory leaves an oscillating window alone
    p = Params(k=5.5, tau=10.0)
    assert rest_exponent(p) < 0
    y = np.sin(2 * np.pi * T / 10.7) + 0.3 * np.sin(4 * np.pi * T / 10.7 + 1.0)
    s = classify(T, rest_window(0.0) + np.vstack([np.zeros_like(T), y, *np.zeros((3, len(T)))]),
                 p=p)
    assert (s.regime, s.attractor) == ("oscillatory", "periodic"), s


def test_a_linear_transient_below_the_hopf_point_stays_sliding():
    # the kink's echoes at tau = 60 and delta = 1e-6, 1% below k_H: they fade
    rng = np.random.default_rng(1)
    pulses = sum(a * np.exp(-((T % 60.0) - c) ** 2) for a, c in zip(rng.uniform(1e-6, 3e-6, 3),
                                                                      (10.0, 25.0, 41.0), strict=True))
    p = Params(k=0.99 * hopf_k(60.0, Params().F1), tau=60.0, delta=1e-6)
    w = rest_window(0.0)
    w[1] = pulses * 0.9
    mid = rest_window(0.0)
    mid[1] = pulses
    s = classify(T + 9.9e4, w, mid_t=T + 4.9e4, mid=mid, p=p)
    assert (s.regime, s.attractor) == ("sliding", "fixed-point"), s
    assert s.flags == ("linear-transient",)


@pytest.mark.slow
def test_the_conclusions_point_is_not_sliding_but_headed_for_the_cycle():
    # k = 6, tau = 60, delta = 1e-6 (0.4% past k_H(60) = 5.977): the window holds the
    # kink's echoes about the unstable rest state; the continuation from the subcritical
    # Hopf point finds the stable large cycle at k = 6 (period ~60.7, amplitude ~2.4)
    rng = np.random.default_rng(1)
    pulses = sum(a * np.exp(-((T % 60.0) - c) ** 2) for a, c in zip(rng.uniform(1e-6, 3e-6, 3),
                                                                      (10.0, 25.0, 41.0), strict=True))
    p = Params(k=6.0, tau=60.0, delta=1e-6)
    w = rest_window(0.0)
    w[1] = pulses * 0.9
    s = classify(T + 9.9e4, w, mid_t=T + 4.9e4, mid=w, p=p)
    assert (s.regime, s.attractor) == ("oscillatory", "unstable-fixed-point"), s
    assert set(s.flags) == {"linear-transient", "not-departed"} and not s.settled
    assert "subcritical" in s.detail
    h = heading(p)
    period = float(h.reason.split("period ")[1].split(",")[0])
    assert period == pytest.approx(60.66, rel=2e-3)


@pytest.mark.slow
def test_runs_just_past_the_exact_hopf_point_at_tau_60_are_not_sliding():
    # short runs (t_end = 3000, Euler as the paper's) from delta = 1e-6: the window sits at
    # the rest state on both sides of k_H(60) from the exact formula; only theory tells them
    # apart
    settings = SolverSettings(t_end=3000.0, lyap=False)
    k_h = hopf_k(60.0, Params().F1)
    above = run_point(Params(k=k_h * 1.002, tau=60.0, delta=1e-6), settings).summary
    below = run_point(Params(k=k_h * 0.99, tau=60.0, delta=1e-6), settings).summary
    assert above.regime != "sliding" and above.attractor == "unstable-fixed-point", above
    assert "not-departed" in above.flags
    assert (below.regime, below.attractor) == ("sliding", "fixed-point"), below
    assert "not-departed" not in below.flags


def test_beyond_the_largest_delay_walked_the_regime_is_undetermined_saying_why():
    # tau = 100, 0.5% past k_H: unstable by theory, the branch walk too costly (core.heading)
    p = Params(k=1.005 * hopf_k(100.0, Params().F1), tau=100.0, delta=1e-6)
    s = classify(T, rest_window(), p=p)
    assert (s.regime, s.attractor) == ("undetermined", "unstable-fixed-point"), s
    assert "not-departed" in s.flags and "beyond tau = 60" in s.detail


def test_strong_noise_moves_the_hopf_point_below_the_gate_and_the_root_is_computed():
    # d = 0.01 lowers the Hopf point at tau = 10 by 3.6% (5.9251 against 6.1485): a point
    # 2.5% below the noise-free k_H is already past it
    p = Params(k=0.975 * hopf_k(10.0, Params().F1), tau=10.0, d=0.01)
    assert p.k > hopf_point(p, "k").value
    assert rest_exponent(p) > NEUTRAL_TOL
