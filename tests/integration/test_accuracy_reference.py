"""The accuracy estimate (core.accuracy) against independent references.

* tau = 0.5, k = 40: scipy's Radau by the method of steps (tests/radau_reference.py,
  rtol 1e-8; 23 s of CPU to t = 300) gives a peak-to-peak m_y of 1.456592 on the cycle,
  with RK4 to 1e-7 (its maxima agree to 1e-8 from t = 250 on: the cycle is reached); the
  paper's Euler at dt = 1e-3 gives 1.5332, 5.3 % too large.
* tau = 0.5, k = 37.6, 0.5 % past the Hopf point k_H = 37.40, where Euler's anti-damping
  moves the onset: Euler's 0.790 against RK4's 0.496 at dt = 1e-4 (59 % too large, the
  referee's "53 %" kind of error); the estimate says 44 %.
"""

from __future__ import annotations

import numpy as np
import pytest

from core.classify import find_peaks
from core.params import Params
from core.point import run_point
from core.solve import SolverSettings
from tests.radau_reference import radau

pytestmark = pytest.mark.computation  # only computes: beside the slow tiers (tests/xdist_plan.py)


def refined_amplitude(t: np.ndarray, y: np.ndarray) -> float:
    _, top = find_peaks(t, y)
    _, low = find_peaks(t, -y)
    return float(top.max() + low.max())


def test_euler_at_tau_half_against_radau() -> None:
    p = Params(tau=0.5, k=40.0)
    ref = radau(k=p.k, tau=p.tau, delta=p.delta, t_end=300.0)
    assert not ref.failed
    t = np.arange(250.0, 300.0, 0.01)
    exact = refined_amplitude(t, ref(t)[1])
    r = run_point(p, SolverSettings(t_end=500.0, lyap=False))  # 300, 400: s_y < 0 in a
    assert r.settings.method == "euler"  # sample, and the stiff scheme's run is 7e-5 off
    true = refined_amplitude(r.trajectory.window_t, r.trajectory.window[1]) / exact - 1.0
    assert true == pytest.approx(0.0526, abs=0.001)
    assert "dt-sensitive" in r.summary.flags
    assert true / 2 <= r.as_record()["dt_error"] <= 2 * true
    # RK4 at dt = 1e-2 is 2.68e-6 too small there, and the estimate says -2.68e-6
    rk4 = run_point(p, SolverSettings(method="rk4", dt=1e-2, t_end=300.0, lyap=False))
    true = refined_amplitude(rk4.trajectory.window_t, rk4.trajectory.window[1]) / exact - 1.0
    assert rk4.accuracy.amplitude == pytest.approx(true, rel=0.1)
    assert "dt-sensitive" not in rk4.summary.flags and rk4.accuracy.value < 1e-5


def test_euler_just_past_the_hopf_point_is_tens_of_per_cent_off_and_flagged() -> None:
    p = Params(tau=0.5, k=37.6)
    s = SolverSettings(t_end=4e3, lyap=False)
    r = run_point(p, s)
    ref = run_point(p, SolverSettings(method="rk4", dt=1e-4, t_end=4e3, lyap=False))
    true = r.summary.amplitude / ref.summary.amplitude - 1.0
    assert true > 0.5
    assert "dt-sensitive" in r.summary.flags
    assert true / 2 <= r.as_record()["dt_error"] <= 2 * true
    assert r.summary.regime == ref.summary.regime  # the label looks right
