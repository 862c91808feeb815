"""The accuracy of every run: core.accuracy's shadow estimate of the
scheme's error at its step, the field ``dt_error`` and the flag ``dt-sensitive``.

The high-frequency point: tau = 0.5, k = 40 (past the Hopf point k_H = 37.40; period 0.79,
omega ~ 8). The paper's Euler at dt = 1e-3 gives a peak-to-peak m_y of 1.5332; RK4 at
dt = 1e-3 and 5e-4 agree on 1.456592 to 3e-10, so Euler's amplitude is 5.3 % too large.
At k = 39 it is 8.5 %. The slow point: k = tau = 10, RK4 at dt = 1e-2, errors near 1e-9.
"""

from __future__ import annotations

import json
import math
from dataclasses import replace

import numpy as np
import pytest

from core.accuracy import TOLERANCE, finer, hermite, start_of
from core.classify import classify
from core.params import Params
from core.point import PointResult, run_batch, run_point
from core.solve import SolverSettings
from slopetui.cli import main

FAST = Params(tau=0.5, k=40.0)
SHORT = SolverSettings(t_end=500.0, lyap=False)


def reference_amplitude(p: Params, t_end: float) -> float:
    """Peak-to-peak m_y in the window of RK4 at dt = 5e-4, checked against dt = 1e-3: the
    independent reference (a finer step of a fourth-order scheme)."""
    a, b = (run_point(p, SolverSettings(method="rk4", dt=dt, t_end=t_end, lyap=False))
            .summary.amplitude for dt in (1e-3, 5e-4))
    assert a == pytest.approx(b, rel=1e-7)  # converged: the reference's own error
    return b


@pytest.mark.parametrize("k", [40.0, 39.0])
def test_euler_at_high_frequency_is_flagged_within_a_factor_two_of_its_true_error(k) -> None:
    """Euler's amplitude is 5-9 % too large; the estimate says so (it was NaN, unflagged)."""
    p = Params(tau=0.5, k=k)
    r = run_point(p, SHORT)
    rec = r.as_record()
    true = r.summary.amplitude / reference_amplitude(p, SHORT.t_end) - 1.0
    assert true > 0.05
    assert "dt-sensitive" in rec["flags"].split(",")
    assert true / 2 <= rec["dt_error"] <= 2 * true
    assert r.accuracy.amplitude == pytest.approx(true, rel=0.1)  # measured: 3-4 % off
    assert "dt error" not in rec["detail"]  # the classifier's words alone (the report counts them)


def test_rk4_at_k_tau_10_is_not_flagged_and_its_error_is_small() -> None:
    r = run_point(Params(k=10.0, tau=10.0), SolverSettings(method="rk4", dt=1e-2, t_end=4e3,
                                                           lyap=False))
    rec = r.as_record()
    assert r.summary.attractor == "periodic"
    assert "dt-sensitive" not in rec["flags"].split(",")
    assert 0.0 < rec["dt_error"] < 1e-6  # RK4's errors near 1e-9 at dt = 1e-2
    assert not r.accuracy.label_changed


def test_euler_at_k_tau_10_is_below_the_tolerance_and_matches_rk4() -> None:
    """Euler's amplitude error at k = tau = 10 is 7e-4 (against RK4): estimated to 10 %."""
    p = Params(k=10.0, tau=10.0)
    r = run_point(p, SolverSettings(t_end=4e3, lyap=False))
    ref = run_point(p, SolverSettings(method="rk4", dt=1e-2, t_end=4e3, lyap=False))
    true = r.summary.amplitude / ref.summary.amplitude - 1.0
    assert r.accuracy.amplitude == pytest.approx(true, rel=0.1)
    assert r.accuracy.value < TOLERANCE and "dt-sensitive" not in r.summary.flags


def test_at_rest_the_estimate_is_nan_with_its_reason() -> None:
    r = run_point(Params(k=4.0, tau=10.0), SolverSettings(t_end=2e3, lyap=False))
    assert r.summary.attractor == "fixed-point"
    assert math.isnan(r.as_record()["dt_error"]) and "dt-sensitive" not in r.summary.flags
    assert "at rest" in r.accuracy.text()


def test_batched_runs_get_the_same_estimate_from_their_window() -> None:
    """The batched kernels hand over no final state: the shadow starts from the window's
    samples (Hermite in m_x with slope m_y), and agrees with the single run's."""
    points = [Params(tau=0.5, k=k) for k in (38.0, 39.0, 40.0, 41.0)]
    batch = run_batch(points, SHORT)
    # a lane re-integrated by the stiff scheme (k = 38: s_y < 0 in a sample) has its state
    assert sum(b.trajectory.final is None for b in batch) >= 3
    for p, b in zip(points, batch, strict=True):
        single = run_point(p, SHORT)
        assert b.accuracy.value == pytest.approx(single.accuracy.value, rel=1e-5)
        assert ("dt-sensitive" in b.summary.flags) == ("dt-sensitive" in single.summary.flags)


def test_the_window_gives_the_final_state_of_the_kernel() -> None:
    """start_of from the window alone (as for a batched lane) against the kernel's hand-over."""
    tr = run_point(FAST, SHORT).trajectory
    rebuilt = start_of(replace(tr, final=None))
    assert np.array_equal(rebuilt.now, tr.final.now)
    assert rebuilt.m_x == pytest.approx(tr.final.m_x, abs=1e-5)  # Euler: slope m_y to O(dt)


def test_hermite_and_finer_histories() -> None:
    t = np.linspace(0.0, 1.0, 101)
    at = np.linspace(0.0, 1.0, 1001)
    assert hermite(t, np.sin(5 * t), 5 * np.cos(5 * t), at) == pytest.approx(np.sin(5 * at), abs=1e-7)
    tr = run_point(FAST, SHORT).trajectory
    half = finer(tr.final)
    assert half.dt == tr.final.dt / 2 and half.m_x.size == 2 * tr.final.m_x.size
    assert np.array_equal(half.m_x[::2], tr.final.m_x)
    empty = finer(type(tr.final)(0.0, 1e-3, tr.final.now, np.zeros(0)))  # tau = 0
    assert empty.m_x.size == 0


def test_run_prints_the_estimate_and_json_has_it(capsys) -> None:
    args = ["run", "--k", "40", "--tau", "0.5", "--t-end", "500", "--no-lyap"]
    assert main(args) == 0
    text = capsys.readouterr().out
    line = next(s for s in text.splitlines() if s.startswith("dt error"))
    assert "amplitude +0.05" in line and "dt-sensitive" in line
    assert main([*args, "--json"]) == 0
    rec = json.loads(capsys.readouterr().out)
    assert 0.025 < rec["dt_error"] < 0.11 and "dt-sensitive" in rec["flags"]


def test_a_shadow_still_relaxing_is_continued_and_called_a_lower_bound(monkeypatch) -> None:
    """With no change small enough to count as relaxed, the span doubles twice (200 ->
    800) and the estimate says it is a lower bound; the continued shadows measure the same
    error (the dt / 2 shadow had relaxed: within 1e-3 of itself)."""
    import core.accuracy as accuracy
    tr = run_point(FAST, SolverSettings(t_end=2000.0, lyap=False))  # room: 2 windows of 1000
    monkeypatch.setattr(accuracy, "RELAXED", -1.0)
    monkeypatch.setattr(accuracy, "RELAXED_FLOOR", -1.0)
    e = accuracy.dt_error(tr.trajectory, tr.summary)
    assert e.span == pytest.approx(4 * tr.accuracy.span, rel=1e-6) and not e.relaxed
    assert "lower bound" in e.reason
    assert e.value == pytest.approx(tr.accuracy.value, rel=1e-3)


def test_euler_oscillating_where_the_model_rests_is_flagged() -> None:
    """At tau = 0.5, k = 37.2, below the Hopf point k_H = 37.40, the model rests (RK4 at
    dt = 1e-3: sliding), but Euler's anti-damping sustains a cycle of amplitude 0.45: the
    label itself is the scheme's. The dt / 2 shadow decays; the estimate (a lower bound,
    still relaxing after its doublings) is several times the amplitude."""
    p = Params(tau=0.5, k=37.2)
    s = SolverSettings(t_end=4e3, lyap=False)
    ref = run_point(p, SolverSettings(method="rk4", dt=1e-3, t_end=4e3, lyap=False))
    assert ref.summary.regime == "sliding"
    r = run_point(p, s)
    assert r.summary.regime == "oscillatory" and "dt-sensitive" in r.summary.flags
    assert r.accuracy.value > 1.0


def window_period(r: PointResult) -> float:
    """The return time the run's own window shows: what the estimate is about. The stored
    period of a certified orbit is the certified orbit's (core.certify), not the scheme's."""
    tr = r.trajectory
    return classify(tr.window_t, tr.window, p=tr.params).period


@pytest.mark.parametrize("k", [12.0, 16.0])
def test_long_delay_orbits_are_measured_on_their_major_maxima(k) -> None:
    """Euler at tau = 20 (period 20.4): a shallow stick-phase maximum in some cycles (k =
    12) and two maxima at unequal, drifting spacings (k = 16) made the shadows' period 9 %
    and 2x off and flagged the runs; their amplitude errors against RK4 are below 1e-3.
    At k = 12 the dt / 2 shadow's return time swings about its limit for ~1000 time units
    (the estimate says it is a lower bound); its period error is RK4's to a factor 2. At
    k = 16 both runs are multi-slip transients (Euler's return has 2 maxima, RK4's 3):
    their periods agree to 2e-6, the estimate says < 1e-3."""
    p = Params(k=k, tau=20.0)
    r = run_point(p, SolverSettings(t_end=2e4, lyap=False))
    ref = run_point(p, SolverSettings(method="rk4", t_end=2e4, lyap=False))
    assert "dt-sensitive" not in r.summary.flags and r.accuracy.value < 1e-3
    assert r.accuracy.amplitude == pytest.approx(r.summary.amplitude / ref.summary.amplitude - 1,
                                                 rel=0.1)
    true = window_period(r) / window_period(ref) - 1
    if k == 12.0:
        assert true / 2 <= r.accuracy.period <= 2 * true


@pytest.mark.parametrize("method", ["euler", "stiff"])
def test_the_period_error_of_each_first_order_scheme(method) -> None:
    """tau = 0.5, k = 40 against RK4 at dt = 1e-3: Euler's period is 1.68e-3 too long,
    the stiff scheme's 3.84e-4; the estimates say 1.65e-3 and 3.83e-4."""
    p = Params(tau=0.5, k=40.0)
    r = run_point(p, SolverSettings(method=method, t_end=2000.0, lyap=False))
    ref = run_point(p, SolverSettings(method="rk4", dt=1e-3, t_end=2000.0, lyap=False))
    assert r.settings.method == method
    assert r.accuracy.period == pytest.approx(window_period(r) / window_period(ref) - 1, rel=0.1)
