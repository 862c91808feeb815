"""The original N-block model (eq. 5) and its convergence to the mean field."""

from __future__ import annotations

import numpy as np
import pytest

from core.nblock import compare_with_mean_field, simulate_ensemble
from core.params import Params
from slopetui.cli import main


def eq5_numpy(p: Params, x: np.ndarray, y: np.ndarray, dt: float, n_steps: int) -> tuple:
    """A plain transcription of eq. 5 without noise (d = 0), for checking the kernel."""
    n_delay = round(p.tau / dt)
    hist = [x.copy() for _ in range(n_delay)]  # x(t - tau) ... history x(0)
    kappa = p.k / len(x)
    F = lambda v: p.a * v**3 - p.b * v**2 + p.c * v  # noqa: E731 (eq. 1)
    for _ in range(n_steps):
        x_tau = hist.pop(0)
        hist.append(x.copy())
        coupling = kappa * (x_tau.sum() - x_tau) - kappa * (len(x) - 1) * x
        x, y = x + dt * y, y + dt * (F(p.v) - F(p.v + y) + coupling)
    return x, y


def test_the_kernel_is_eq_5():
    p = Params(d=0.0, tau=0.05, k=7.0, delta=0.1)
    ens = simulate_ensemble(p, 5, t_end=0.5, dt=0.01, sample_dt=0.5, seed=3)
    rng = np.random.default_rng(3)
    z = rng.standard_normal(5)
    z = (z - z.mean()) / z.std()
    x0 = p.delta + np.sqrt(p.delta) * z
    x, y = eq5_numpy(p, x0, x0.copy(), 0.01, 50)
    assert ens.moments[0, -1] == pytest.approx(x.mean(), rel=1e-12)
    assert ens.moments[1, -1] == pytest.approx(y.mean(), rel=1e-12)
    assert ens.moments[3, -1] == pytest.approx(y.var(), rel=1e-10)


def test_the_ensemble_starts_on_eq_19_for_any_n():
    for n in (2, 10, 1000):
        ens = simulate_ensemble(Params(delta=0.1), n, t_end=1.0, dt=0.01, sample_dt=1.0)
        assert ens.moments[:, 0] == pytest.approx([0.1] * 5, rel=1e-12)


def m_y_error(n: int, d: float, seed: int = 0) -> float:
    c = compare_with_mean_field(Params(d=d, tau=10.0, k=10.0, delta=0.1), n, 50.0, dt=1e-2,
                                seed=seed)
    return c.errors["m_y"]


def test_the_ensemble_converges_to_the_mean_field_as_n_grows():
    errors = [m_y_error(n, 1e-4) for n in (10, 100, 1000)]
    assert errors[0] > errors[1] > errors[2]
    assert errors[2] < 0.15 < errors[0]


def test_more_noise_takes_the_ensemble_away_from_the_gaussian_closure():
    errors = [m_y_error(1000, d) for d in (1e-4, 1e-2, 1e-1)]
    assert errors[0] < errors[1] < errors[2]
    assert errors[2] > 1.5 * errors[0]


def test_the_nblock_command(capsys):
    code = main(["nblock", "--n", "20,200", "--d", "1e-4", "--t-end", "20", "--dt", "0.01",
                 "--no-plot"])
    out = capsys.readouterr().out
    assert code == 0 and "closure" in out and out.count("1e-04") + out.count("0.0001") >= 2
    assert "Gaussian closure" in out


@pytest.mark.parametrize("args, message", [
    (["--n", "1"], "--n: each N must be in 2..200000"),
    (["--n", "ten"], "--n: expected a comma-separated list"),
    (["--d", "-1"], "--d: noise intensities must be >= 0"),
    (["--tau", "-3"], "tau"),
])
def test_bad_nblock_input(capsys, args, message):
    code = main(["nblock", *args, "--no-plot"])
    assert code == 2 and message in capsys.readouterr().err
