"""lambda_max: equal to the leading root in sliding, zero on limit cycles."""

from __future__ import annotations

import numpy as np
import pytest

from core.lyapunov import estimate, format_with_error, running
from core.params import Params
from core.point import run_point
from core.solve import SolverSettings, simulate
from core.stability import leading_exponent, leading_root


@pytest.mark.parametrize(
    "method,k,tau,t_end",
    [("euler", 4.0, 10.0, 1e5), ("rk4", 4.0, 10.0, 1e5), ("rk4", 5.0, 2.0, 2e4), ("rk4", 12.0, 0.2, 2e3)],
)
def test_sliding_lambda_is_the_leading_root(method, k, tau, t_end):
    p = Params(k=k, tau=tau)
    r = run_point(p, SolverSettings(method=method, t_end=t_end))
    assert r.summary.regime == "sliding"
    root = leading_exponent(p)
    # within 3 standard errors, plus the O(d) shift of the drifting state (~1e-5)
    assert abs(r.lyap.value - root) < 3 * r.lyap.error + 2e-5 + 1e-3 * abs(root), (r.lyap, root)


def test_small_tau_sliding_is_led_by_the_variance_block():
    p = Params(k=12.0, tau=0.2)
    assert leading_root(p).real < -10
    assert leading_exponent(p) == pytest.approx(-p.F1, rel=1e-12)
    assert leading_exponent(p.with_(k=0.0)) == pytest.approx(-p.F1, rel=1e-12)  # no zero root


@pytest.mark.parametrize("method", ["euler", "rk4"])
def test_limit_cycle_lambda_is_zero(method):
    r = run_point(Params(k=10.0, tau=10.0), SolverSettings(method=method, t_end=2e4))
    assert r.summary.regime == "oscillatory"
    assert abs(r.lyap.value) < 3 * r.lyap.error + 1e-5, r.lyap


def test_without_translation_projection_every_state_would_look_neutral():
    """The projection matters: the sliding lambda is clearly negative, not ~0."""
    r = run_point(Params(k=4.0, tau=10.0), SolverSettings(method="rk4", t_end=2e4))
    assert r.lyap.value < -10 * r.lyap.error


def test_block_statistics():
    logs = np.full(100, -0.5)               # exact growth of e^{-0.5} per interval of 2
    e = estimate(logs, 2.0)
    assert e.value == pytest.approx(-0.25) and e.error == pytest.approx(0.0, abs=1e-15)
    assert e.t_measured == pytest.approx(100.0) and e.n_blocks == 20
    rng = np.random.default_rng(1)
    noisy = estimate(rng.normal(0.0, 1.0, 20000), 1.0)
    assert abs(noisy.value) < 4 * noisy.error and 0.002 < noisy.error < 0.02
    t, lam = running(logs, 2.0, points=10)
    assert len(t) == 10 and np.allclose(lam, -0.25)


def test_paper_notation():
    assert format_with_error(0.0008, 0.0009) == "0.0008(9)"
    assert format_with_error(-0.15, 0.06) == "-0.15(6)"
    assert format_with_error(-0.12, 0.03) == "-0.12(3)"


def quotient_norm(tr_plus, tr_minus, eps: float, method: str) -> float:
    """|d X / d delta| at the end of the run, in the kernels' norm (translation removed).

    The window holds every step of the last tau: the current state and the N before it.
    """
    d = (tr_plus.window - tr_minus.window) / (2 * eps)
    dt = tr_plus.grid.dt
    now = d[:, -1]
    hist_x = d[0, :-1] - now[0]
    acc = np.sum(hist_x**2) + (np.sum(d[1, :-1] ** 2) if method == "rk4" else 0.0)
    return float(np.sqrt(now[1] ** 2 + now[2] ** 2 + now[3] ** 2 + now[4] ** 2 + dt * acc))


@pytest.mark.parametrize("method", ["euler", "rk4"])
def test_tangent_is_the_exact_derivative_of_the_discrete_map(method):
    """A delta-perturbation is the kernel's initial tangent (0, 1, 1, 1, 1; history 0) plus
    the neutral translation (1, 0, 0, 0, 0; history 1), so in the quotient norm a central
    difference in delta must give exp(sum of log-growths)."""
    eps, tau, dt = 1e-7, 1.0, 0.01
    s = SolverSettings(method=method, dt=dt, t_end=20.0, window=tau)   # window = every step
    base = Params(k=10.0, tau=tau, delta=0.1)
    tr = simulate(base, s)
    plus = simulate(base.with_(delta=0.1 + eps), s)
    minus = simulate(base.with_(delta=0.1 - eps), s)
    assert plus.window.shape[1] == round(tau / dt) + 1
    assert len(tr.lyap_logs) == 20
    fd = quotient_norm(plus, minus, eps, method)
    assert np.log(fd) == pytest.approx(tr.lyap_logs.sum(), abs=1e-6)
