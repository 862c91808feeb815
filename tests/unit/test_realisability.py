"""Realisability along the whole trajectory: the kernels' running minima
of s_x, s_y and s_x s_y - u^2, the first violation, and the flag ``unrealisable``.

The point: k = 2, tau = 10 (the bistable band below the Hopf point 6.146), delta = 2. RK4
at dt = 1e-2 drives s_y to -3.3e-4 between t = 0.17 and 0.18 and back, the dip the referee
reported; the exact solution does not: eqs. 6c-6e are a Lyapunov equation, which keeps the
covariance positive semidefinite, and scipy's Radau (tests/radau_reference.py) grazes s_y =
+1.9e-5 at t = 0.1764, inside the kernel's dip. The same scheme at dt / 2 keeps s_y
positive, and its first step's s_x s_y - u^2 < 0 (from eq. 19's singular start) shrinks
as dt^5.
"""

from __future__ import annotations

import numpy as np
import pytest

from core.batch import simulate_batch
from core.closure import REALISABLE_TOL
from core.params import Params
from core.point import run_point
from core.solve import SolverSettings, make_grid, simulate
from slopetui.cli.run import render_text
from tests.radau_reference import radau

DIP = Params(k=2.0, tau=10.0, delta=2.0)


def dense(p: Params, method: str, t_end: float, dt: float | None = None):
    """A run whose trace holds the state of every step: the dense reference for the
    kernel's running minima."""
    s = SolverSettings(method=method, t_end=t_end, dt=dt, lyap=False)
    n = make_grid(p, s).n_steps
    return simulate(p, SolverSettings(method=method, t_end=t_end, dt=dt, lyap=False,
                                      trace_points=n + 1))


@pytest.mark.parametrize("method", ["euler", "rk4", "stiff"])
def test_running_minima_equal_the_dense_minima(method: str) -> None:
    """Each kernel's minima are those of its own trajectory sampled at every step, and its
    first violation is the first such sample below the tolerance."""
    tr = dense(DIP, method, 1.0)
    assert tr.trace.shape[1] == tr.grid.n_steps + 1  # every step, the start and the end
    s_x, s_y, u = tr.trace[2], tr.trace[3], tr.trace[4]
    det = s_x * s_y - u * u
    real = tr.realisability
    assert real.min_s_x == s_x.min() and real.min_s_y == s_y.min()
    assert real.min_det == pytest.approx(det.min(), abs=1e-15)  # the kernel fuses a multiply-add
    bad = (s_x < -REALISABLE_TOL) | (s_y < -REALISABLE_TOL) | (det < -REALISABLE_TOL)
    assert real.t_first == (tr.trace_t[np.argmax(bad)] if bad.any() else None)


def test_the_dip_is_seen_between_samples_and_placed_against_radau() -> None:
    """RK4's s_y dips to -3.3e-4 where Radau grazes 0 from above; the run is flagged from
    its first step, where the exact covariance starts on the boundary (s_x s_y = u^2,
    eq. 19), though no sample of a long run sees the dip."""
    ref = radau(k=DIP.k, tau=DIP.tau, delta=DIP.delta, t_end=1.0)
    t = np.linspace(0.0, 1.0, 100_001)
    z = ref(t)
    t_graze = t[np.argmin(z[3])]
    assert 0.17 < t_graze < 0.18 and z[3].min() > 1e-5  # the exact s_y stays positive
    assert abs(z[2, 0] * z[3, 0] - z[4, 0] ** 2) < 1e-15  # the boundary at t = 0

    tr = dense(DIP, "rk4", 1.0)
    dip = tr.trace_t[tr.trace[3] < -REALISABLE_TOL]
    assert dip.min() <= t_graze <= dip.max() + tr.grid.dt  # the kernel's dip, at the graze
    assert tr.realisability.min_s_y == pytest.approx(-3.30e-4, rel=0.01)
    assert tr.realisability.t_first == pytest.approx(tr.grid.dt)  # one step from t = 0
    half = dense(DIP, "rk4", 1.0, dt=5e-3).realisability  # the scheme's violations, not the model's:
    assert half.min_s_y > 0.0 and half.min_det > tr.realisability.min_det / 16  # ~dt^5 at the start

    r = run_point(DIP, SolverSettings(method="rk4", t_end=2000.0, window=100.0, lyap=False))
    rec = r.as_record()
    assert "unrealisable" in rec["flags"] and "closure-breakdown" not in rec["flags"]
    assert "unrealisable from t = 0.01 (min s_x" in rec["detail"]
    assert "s_y -0.00033" in rec["detail"]
    assert "covariance unrealisable from t = 0.01" in render_text(r)


@pytest.mark.parametrize("method", ["rk4", "stiff"])
def test_a_realisable_run_is_not_flagged(method: str) -> None:
    """The defaults at k = 12, tau = 10 stay realisable under RK4 and the stiff scheme
    (their only negative value is round-off at t = 0: s_x s_y - u^2 = -8.3e-19)."""
    r = run_point(Params(k=12.0, tau=10.0), SolverSettings(method=method, t_end=50.0, lyap=False))
    real = r.trajectory.realisability
    assert real.realisable and real.min_s_y > 0.0 and real.min_det > -1e-18
    assert "unrealisable" not in r.summary.flags and "unrealisable" not in r.summary.detail
    assert "covariance realisable at every step" in render_text(r)


def test_euler_leaves_at_its_first_step() -> None:
    """The paper's Euler at dt = 1e-3 breaks the covariance at its first step from eq. 19's
    singular start (s_y then reaches -1.1e-3 at t = 0.07), at the defaults too."""
    real = simulate(Params(k=12.0, tau=10.0), SolverSettings(t_end=5.0, lyap=False)).realisability
    assert real.t_first == pytest.approx(1e-3) and real.min_s_y == pytest.approx(-1.147e-3, rel=1e-3)


@pytest.mark.parametrize("method", ["euler", "rk4"])
@pytest.mark.parametrize("lyap", [False, True])
def test_batched_and_single_kernels_agree(method: str, lyap: bool) -> None:
    """The batch's rows of minima and its first violation (found by the single kernel up
    to the chunk where a lane crossed) equal the single kernel's run by run."""
    points = [Params(k=k, tau=10.0, delta=delta) for k in (2.0, 4.0, 12.0) for delta in (0.1, 2.0)]
    points += [Params(k=3.0, tau=10.0, delta=0.5), Params(k=5.0, tau=10.0, delta=1.0)]
    s = SolverSettings(method=method, t_end=30.0, lyap=lyap)
    for p, tb in zip(points, simulate_batch(points, s), strict=True):
        single, batched = simulate(p, s).realisability, tb.realisability
        assert batched.t_first == single.t_first, p
        for a, b in ((batched.min_s_x, single.min_s_x), (batched.min_s_y, single.min_s_y),
                     (batched.min_det, single.min_det)):
            assert a == pytest.approx(b, rel=1e-12, abs=1e-18), p


def test_the_report_counts_the_classifiers_words() -> None:
    """The detail of an unrealisable run ends in its own minima; the report's count of
    kinds (reproduce.measures.details) takes the classifier's words before them."""
    from core.closure import Realisability, classifier_detail
    a = Realisability(-1e-5, -1e-3, -2e-4, 0.001).text()
    b = Realisability(-2e-5, -3e-3, -5e-4, 0.001).text()
    assert classifier_detail(f"period-2; {a}") == classifier_detail(f"period-2; {b}") == "period-2"
    assert classifier_detail("8 switches") == "8 switches"
