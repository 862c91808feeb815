"""Certification's edges, fast (the certificates themselves: tests/integration/test_certify.py)."""

from __future__ import annotations

from core.certify import STABLE_MARGIN, VERDICT_TEXT, orbit_verdict
from core.params import Params
from core.point import run_point
from core.solve import SolverSettings


def test_a_vanishing_stiffness_leaves_linear_theory_undecided_not_a_traceback():
    # k = 3.5e-283 (hypothesis found it): no root of the delay factor is away from 0, and
    # core.stability says so with an ArithmeticError; the run is not certified, saying why
    r = run_point(Params(k=3.51259e-283, tau=14, d=0.0, delta=0.0), SolverSettings(t_end=50))
    assert not r.certificate.certified
    assert r.certificate.text == "linear theory undecided: no nonzero root found"


def test_an_orbit_within_the_margin_of_the_circle_is_neither_stable_nor_unstable():
    assert orbit_verdict(0.7) == "stable"
    assert orbit_verdict(1 - 2 * STABLE_MARGIN) == "stable"
    assert orbit_verdict(0.9999913) == "marginal"        # the 3-slip orbit, k = 18, tau = 10
    assert orbit_verdict(1.0) == "marginal"              # the 2-slip orbit's -1.00000000
    assert orbit_verdict(1 + 0.5 * STABLE_MARGIN) == "marginal"
    assert orbit_verdict(1 + 2 * STABLE_MARGIN) == "unstable"
    assert "undetermined" in VERDICT_TEXT["marginal"]
    assert "unstable" not in VERDICT_TEXT["marginal"]
