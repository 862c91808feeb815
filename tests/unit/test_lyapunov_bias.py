"""lambda_max beside the continuous model's exponent (core.lyapunov_bias)."""

from __future__ import annotations

import math

from core.lyapunov_bias import bias_note, continuous_exponent, relative_bias
from core.params import Params
from core.point import run_point
from core.solve import SolverSettings
from core.stability import leading_exponent


def test_at_the_fixed_point_the_bias_is_first_order_in_dt():
    """k = 5, tau = 2, d = 0: the Euler map's exponent differs from the leading root by
    O(dt), so halving dt halves the bias (measured 7.5e-4 relative at dt 1e-3 with d = 1e-4)."""
    p = Params(k=5.0, tau=2.0, d=0.0, delta=1e-3)
    exact = continuous_exponent(p, "fixed-point")
    assert exact is not None and exact.value == leading_exponent(p)
    biases = []
    for dt in (2e-3, 1e-3):
        r = run_point(p, SolverSettings(method="euler", dt=dt, t_end=3000.0, lyap=True))
        assert r.summary.attractor == "fixed-point" and r.lyap is not None
        biases.append(exact.bias(r.lyap.value))
        assert relative_bias(r.lyap.value, exact) < 0.02
    assert 1.6 < biases[0] / biases[1] < 2.4


def test_a_periodic_orbit_has_the_flow_direction_zero():
    p = Params(k=10.0, tau=10.0)
    exact = continuous_exponent(p, "periodic")
    assert exact is not None and exact.value == 0.0
    assert math.isnan(relative_bias(1e-5, exact))
    note = bias_note(p, "periodic", "rk4", 0.01, 2e-6)
    assert "O(dt^4)" in note and "flow direction" in note and "+2.0e-06" in note


def test_where_theory_is_silent_the_note_says_so():
    assert continuous_exponent(Params(), "chaotic") is None
    assert "not known here" in bias_note(Params(), "chaotic", "euler", 1e-3, 0.01)



def test_the_run_detail_shows_the_note_beside_the_running_estimate():
    """The recomputation the run detail draws carries the note, and the lambda_max plot
    shows it in its legend."""
    from slopetui.plots.run_plots import render_lyapunov
    from slopetui.sweeps.recompute import compute_traces
    traces = compute_traces(Params(k=5.0, tau=2.0), SolverSettings(t_end=400.0, lyap=True))
    assert "linear theory" in traces.lambda_note and "euler map" in traces.lambda_note
    text = render_lyapunov(traces.lam_t, traces.lam, estimate="-0.18", note_text="euler map at dt",
                           width=100, height=16, color=False)
    assert "euler map at dt" in text
