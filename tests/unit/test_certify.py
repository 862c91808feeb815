"""Certification's edges, fast (the certificates themselves: tests/integration/test_certify.py)."""

from __future__ import annotations

from core.params import Params
from core.point import run_point
from core.solve import SolverSettings


def test_a_vanishing_stiffness_leaves_linear_theory_undecided_not_a_traceback():
    # k = 3.5e-283 (hypothesis found it): no root of the delay factor is away from 0, and
    # core.stability says so with an ArithmeticError; the run is not certified, saying why
    r = run_point(Params(k=3.51259e-283, tau=14, d=0.0, delta=0.0), SolverSettings(t_end=50))
    assert not r.certificate.certified
    assert r.certificate.text == "linear theory undecided: no nonzero root found"
