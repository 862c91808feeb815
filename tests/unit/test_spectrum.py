"""The top Lyapunov exponents (core.spectrum) against linear theory at a fixed point, and
what they say of a torus or chaos (core.spectrum.evidence). The periodic orbit's check
against its Floquet multipliers takes seconds: tests/integration/test_spectrum_orbit.py."""

from __future__ import annotations

import math

import numpy as np
import pytest

from core.classify import CHAOS_LAMBDA_MIN
from core.params import ParameterError, Params
from core.solve import SolverSettings, make_grid, simulate
from core.spectrum import MAX_EXPONENTS, Spectrum, check_count, check_spectrum, evidence, spectrum
from core.stability import roots

#: A stable rest state with well separated roots: k = 4 < F'^2 / 2, tau = 1, no noise (d = 0:
#: the linearisation is core.stability's, eq. 20).
REST = Params(k=4.0, tau=1.0, d=0.0)


def _theory(p: Params, count: int) -> list[float]:
    """The real parts of the rightmost roots of the linearisation at the fixed point, the
    shift's zero root left out, each complex pair twice: the roots of h (eq. 20) and of the
    variance block (lam + F')(lam^2 + 2 F' lam + 4k)."""
    parts: list[float] = []
    for lam in roots(p.F1, p.k, p.tau, count + 2):
        if abs(lam) < 1e-9:
            continue
        parts += [lam.real] * (2 if abs(lam.imag) > 1e-9 else 1)
    block = np.roots([1.0, 2.0 * p.F1, 4.0 * p.k])
    parts += [-p.F1] + [float(r.real) for r in block]
    return sorted(parts, reverse=True)[:count]


def test_rk4_exponents_at_a_fixed_point_are_the_leading_roots():
    """The top five exponents are the rightmost roots' real parts (-1.0912 twice, -3.0470
    twice, -F' = -3.456), to their errors (RK4 at dt = 0.01 carries a bias of ~1e-8)."""
    sp = spectrum(REST, SolverSettings(method="rk4", t_end=400.0), 5)
    assert sp is not None
    expected = _theory(REST, 5)
    for v, e, x in zip(sp.values, sp.errors, expected, strict=True):
        assert abs(v - x) <= 5.0 * e + 1e-3, (sp.format(), expected)


def test_euler_exponents_are_the_roots_to_the_maps_first_order_bias():
    """Euler's map at dt = 1e-3 is O(dt) off the continuous roots (0.2-1.7% in lambda_max,
    core.lyapunov_bias): the top four within 1%."""
    sp = spectrum(REST, SolverSettings(method="euler", t_end=400.0), 4)
    assert sp is not None
    for v, x in zip(sp.values, _theory(REST, 4), strict=True):
        assert v == pytest.approx(x, rel=1e-2)


def test_the_top_exponent_is_lambda_max_of_the_same_run():
    """The spectrum's first tangent and the kernel's one tangent grow along the same
    direction of the same trajectory: their exponents agree within the errors."""
    from core.point import run_point
    s = SolverSettings(method="rk4", t_end=400.0)
    r = run_point(REST, s, spectrum=2)
    assert r.spectrum is not None and r.lyap is not None
    assert abs(r.spectrum.values[0] - r.lyap.value) <= 3.0 * (r.spectrum.errors[0] + r.lyap.error)
    rec = r.as_record()
    assert rec["spectrum"] == list(r.spectrum.values) and len(rec["spectrum_err"]) == 2
    assert run_point(REST, s).as_record()["spectrum"] == []  # not computed: empty


@pytest.mark.parametrize("given", [0, -1, MAX_EXPONENTS + 1, "x", 2.5, True, None])
def test_the_count_is_bounded(given):
    with pytest.raises(ParameterError, match=rf"spectrum = .* allowed an integer 1 <= N <= {MAX_EXPONENTS}"):
        check_count(given)


def test_a_scheme_without_tangents_and_too_many_exponents_without_a_delay_are_refused():
    with pytest.raises(ParameterError, match="only with --method euler or rk4"):
        check_spectrum(REST, SolverSettings(method="stiff", t_end=100.0), 2)
    with pytest.raises(ParameterError, match="1 <= N <= 4 at tau = 0"):
        check_spectrum(REST.with_(tau=0.0), SolverSettings(t_end=100.0), 5)
    check_spectrum(REST.with_(tau=0.0), SolverSettings(t_end=100.0), 4)


def test_without_a_delay_the_four_exponents_are_the_jacobians():
    """tau = 0: m_y, s_x, s_y, u besides the shift. At the fixed point (d = 0) the Jacobian's
    eigenvalues are those of [[0, 1], [0, -F']] (the shift's 0 left out: -F') and the
    variance block's (-F', -F' +- i sqrt(4k - F'^2))."""
    p = REST.with_(tau=0.0)
    sp = spectrum(p, SolverSettings(method="rk4", t_end=400.0), 4)
    assert sp is not None
    # four equal exponents converge as 1/t, not their errors: -3.4525 to -3.4595 at t = 400
    # (-3.4551 to -3.4569 at 1600)
    assert sp.values == pytest.approx([-p.F1] * 4, rel=2e-3)


def _sp(*pairs: tuple[float, float]) -> Spectrum:
    return Spectrum(tuple(v for v, _ in pairs), tuple(e for _, e in pairs), 1e4)


def test_evidence():
    ev = evidence(_sp((2e-5, 3e-5), (-1e-5, 2e-5), (-0.03, 1e-3)), CHAOS_LAMBDA_MIN)
    assert ev.torus and not ev.chaotic and ev.neutral == 2
    ev = evidence(_sp((0.05, 1e-3), (0.0, 1e-4), (-0.1, 1e-3)), CHAOS_LAMBDA_MIN)
    assert ev.chaotic and not ev.torus
    # positive at 13 sigma but below CHAOS_LAMBDA_MIN: the referee's k = 20, tau >= 60
    ev = evidence(_sp((1.3e-4, 1e-5), (0.0, 1e-5), (-0.01, 1e-3)), CHAOS_LAMBDA_MIN)
    assert not ev.chaotic and not ev.torus and "positive but below" in ev.reason
    ev = evidence(_sp((0.0, 1e-5), (-1e-5, 1e-5), (-2e-5, 1e-5)), CHAOS_LAMBDA_MIN)
    assert not ev.torus and ev.neutral == 3 and "slow transient?" in ev.reason
    ev = evidence(_sp((0.0, 1e-5), (-0.04, 1e-4), (-0.05, 1e-4)), CHAOS_LAMBDA_MIN)
    assert not ev.torus and ev.neutral == 1 and "not quasi-periodic" in ev.reason
    ev = evidence(_sp((0.0, 1e-5), (0.0, 1e-5)), CHAOS_LAMBDA_MIN)
    assert not ev.torus and "--spectrum 3" in ev.reason
    # no error bars (a run too short for two blocks): nothing is known with confidence
    ev = evidence(_sp((1e-6, math.nan), (0.0, math.nan), (-0.1, math.nan)), CHAOS_LAMBDA_MIN)
    assert not ev.torus and not ev.chaotic


def test_more_tangent_memory_than_a_run_may_take_is_refused_with_the_count_that_fits():
    """tau = 1e4, RK4 at dt = 1e-3: each tangent's ring holds 2 x 1e7 values (160 MB): 16
    of them are over the 2 GiB a run may take, 13 fit."""
    p, s = Params(tau=1e4), SolverSettings(method="rk4", dt=1e-3, t_end=2e4)
    with pytest.raises(ParameterError, match=r"spectrum = 16 .* allowed 1 <= N <= 13 at tau = 10000"):
        check_spectrum(p, s, 16)
    check_spectrum(p, s, 13)


def test_a_blow_up_at_the_very_last_step_gives_no_spectrum():
    """The tangent kernels say a blow-up with a negative count, so that one at the last
    step (Euler at dt 0.3, k = 6, tau = 10: step 68 of 68; simulate flags it blown) is not
    taken for a finished run: a count of 68 of 68 alone cannot tell."""
    p = Params(k=6.0, tau=10.0, delta=1e-3)
    dt = 0.3
    steps = [n for n in range(60, 90)
             if simulate(p, SolverSettings(method="euler", dt=dt, t_end=n * dt, window=n * dt / 2,
                                           lyap=False)).blown]
    assert steps, "no blow-up within 90 steps: the case needs another point"
    t_end = steps[0] * dt  # the shortest run that blows up: at its last step
    s = SolverSettings(method="euler", dt=dt, t_end=t_end, window=t_end / 2, lyap=True)
    assert simulate(p, s).steps_done == make_grid(p, s).n_steps
    assert spectrum(p, s, 2) is None
