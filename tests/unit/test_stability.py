"""Linear stability: the exact Hopf curve, the leading root, and the paper's eqs. 26-27."""

from __future__ import annotations

import math

import numpy as np
import pytest

from core.params import Params
from core.stability import (
    characteristic,
    hopf_curve_friction,
    hopf_k,
    hopf_tau,
    leading_root,
    paper_fit_k,
    roots,
    small_tau_k,
)

F1 = Params().F1


@pytest.mark.parametrize("tau", [0.1, 0.5, 1.0, 2.0, 5.0, 10.0, 60.0])
def test_hopf_point_is_a_purely_imaginary_root(tau):
    k = hopf_k(tau, F1)
    omega = math.sqrt(2 * k - F1 * F1)
    assert abs(characteristic(1j * omega, F1, k, tau)) < 1e-9 * k


@pytest.mark.parametrize("tau", [0.1, 0.5, 1.0, 2.0, 5.0, 10.0, 60.0])
def test_leading_root_crosses_zero_on_the_hopf_curve(tau):
    k = hopf_k(tau, F1)
    below = leading_root(Params(k=0.99 * k, tau=tau)).real
    above = leading_root(Params(k=1.01 * k, tau=tau)).real
    assert below < 0 < above


def test_hopf_limits():
    # tau -> 0: k_H ~ pi^2 / (2 tau^2); tau -> inf: k_H -> F'^2 / 2
    assert hopf_k(1e-3, F1) * 1e-6 == pytest.approx(math.pi**2 / 2, rel=1e-2)
    assert hopf_k(1e4, F1) == pytest.approx(F1 * F1 / 2, rel=1e-4)
    taus = np.geomspace(0.05, 100, 40)
    ks = [hopf_k(t, F1) for t in taus]
    assert all(np.diff(ks) < 0)   # the boundary falls monotonically with tau


def test_leading_root_example_of_the_issue():
    r = leading_root(Params(k=4.0, tau=10.0))
    assert r.real == pytest.approx(-0.0039, abs=1e-4)
    assert abs(characteristic(r, F1, 4.0, 10.0)) < 1e-12


def test_roots_include_the_neutral_zero_and_are_roots():
    rs = roots(F1, 4.0, 10.0)
    assert abs(rs[0]) < 1e-9                          # translation mode
    for r in rs:
        assert abs(characteristic(r, F1, 4.0, 10.0)) < 1e-9


def test_stable_for_every_tau_below_half_f1_squared():
    for tau in (0.5, 5.0, 50.0):
        assert leading_root(Params(k=0.9 * F1 * F1 / 2, tau=tau)).real < 0


def test_paper_fit_eq_27_agrees_with_exact_curve():
    """Eq. 27 fits the paper's Euler data (delta = 1e-6); the exact curve must lie within
    the few per cent that Euler at dt = 1e-3 shifts it (numerics note: 4% at tau = 0.1)."""
    for lo, hi in ((0.12, 0.48), (0.5, 4.9)):
        taus = np.linspace(lo, hi, 30)
        exact = np.array([hopf_k(t, F1) for t in taus])
        fit = paper_fit_k(taus)
        assert np.max(np.abs(fit / exact - 1)) < 0.05


def test_eq_26_is_only_qualitative():
    """Eq. 26 gets the 1/tau^2 divergence but not its constant: 0.76 vs pi^2/2."""
    tau = 1e-3
    assert small_tau_k(tau, F1) * tau**2 == pytest.approx((4 * math.sqrt(6) - 6) / 5, rel=1e-2)
    assert hopf_k(tau, F1) * tau**2 == pytest.approx(math.pi**2 / 2, rel=1e-2)


@pytest.mark.parametrize("name", ["a", "b", "c"])
def test_friction_plane_curves_are_on_the_boundary(name):
    p = Params(k=12.0)
    values, taus = hopf_curve_friction(p, name)
    for val, tau in list(zip(values, taus, strict=True))[50:350:60]:
        q = p.with_(**{name: float(val)}, tau=float(tau))
        assert leading_root(q).real == pytest.approx(0.0, abs=1e-7)
        assert hopf_k(float(tau), q.F1) == pytest.approx(p.k, rel=1e-6)


def test_hopf_tau_formula_matches_notes():
    # k_H(10) = 6.149 (numerics note): tau_H at that omega must give back 10
    k = 6.148541335351476
    omega = math.sqrt(2 * k - F1 * F1)
    assert hopf_tau(omega, F1) == pytest.approx(10.0, rel=1e-9)
