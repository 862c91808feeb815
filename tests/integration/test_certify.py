"""Certification (core.certify) against theory and independent computations."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from core.certify import STABLE_MARGIN, certify, relabel
from core.classify import classify
from core.params import Params
from core.periodic_orbit import find_orbit
from core.point import run_batch, run_point
from core.solve import SolverSettings, simulate
from core.stability import hopf_period, leading_exponent

pytestmark = pytest.mark.computation  # only computes: beside the slow tiers (tests/xdist_plan.py)


def test_the_default_orbit_is_certified_as_core_periodic_orbit_finds_it():
    p = Params(k=10, tau=10)
    r = run_point(p, SolverSettings(t_end=2e4))            # Euler, dt 1e-3
    c = r.certificate
    assert c.certified, c.text
    assert "RK4 at dt 0.01" in c.text                      # where it was certified
    orbit = find_orbit(p)                                   # from eq. 19, its own seed
    assert c.period == pytest.approx(orbit.period, rel=1e-9)
    assert c.amplitude == pytest.approx(orbit.amplitude, rel=1e-7)
    assert c.slips == orbit.maxima_per_period == 1
    # the multipliers: the same leading ones, inside the unit circle, the flow's apart
    mine = np.array([complex(*m) for m in r.as_record()["multipliers"]])
    assert np.all(np.abs(mine) < 1 - STABLE_MARGIN)
    assert abs(mine[0]) == pytest.approx(abs(orbit.multipliers.leading), rel=1e-6)
    assert np.all(np.abs(mine - 1) > 1e-3)                  # no flow multiplier among them
    # a period of the Hopf branch's family: 0.99 of 2 pi / omega_H (core.stability)
    assert c.period / hopf_period(p.tau, p.F1) == pytest.approx(1.0, abs=0.05)
    # the labels follow the orbit; the window's own return time is Euler's, 8e-5 away
    assert r.summary.period == c.period
    assert r.summary.period_count == 1 and r.summary.maxima_per_period == 1
    assert abs(r.trajectory.window_t[-1] - 2e4) < 1e-9


def test_an_orbit_seeded_at_twice_its_period_is_certified_at_its_period():
    # the window may return after a multiple of the period: Newton converges at 2 T too
    # (every T-periodic orbit is 2T-periodic), and the shot over T that closes says T
    p = Params(k=10, tau=10)
    r = run_point(p, SolverSettings(t_end=5000, method="rk4", dt=0.01))
    doubled = dataclasses.replace(r.summary, period=2 * r.summary.period, period_count=2)
    c = certify(r.trajectory, doubled)
    assert c.certified, c.text
    assert c.period == pytest.approx(r.certificate.period, rel=1e-9)
    assert c.slips == 1
    # and the label follows the certified orbit, not the window's return
    s = relabel(dataclasses.replace(doubled, regime="complex", detail="period-2, 2 maxima"), c, p)
    assert (s.regime, s.period_count, s.maxima_per_period) == ("oscillatory", 1, 1)
    assert s.detail.startswith("period-1, 1 maximum, 0.99 T_H (certified)")


def test_batched_runs_are_certified_as_single_ones():
    points = [Params(k=10, tau=10), Params(k=4, tau=10)]
    s = SolverSettings(t_end=5000, method="rk4", dt=0.01)
    for one, lane in zip((run_point(p, s) for p in points), run_batch(points, s), strict=True):
        assert lane.certificate.certified, lane.certificate.text
        assert lane.certificate.text == one.certificate.text


def test_a_fixed_point_is_certified_by_its_root_and_its_decay():
    p = Params(k=4, tau=10)
    r = run_point(p, SolverSettings(t_end=2e4))
    c = r.certificate
    assert c.certified, c.text
    assert f"leading root {leading_exponent(p):+.3e}/t" in c.text
    assert "-3.944e-03" in c.text                           # core.stability's root
    assert r.as_record()["multipliers"] == [] and c.slips == 0
    # still decaying in the window: the measured rate beside the root (5.6 % apart)
    p = Params(k=5.8, tau=10)
    r = run_point(p, SolverSettings(t_end=5000))
    c = r.certificate
    assert c.certified, c.text
    assert "window decays at" in c.text and f"{leading_exponent(p):+.3e}" in c.text


def test_an_unstable_rest_state_is_not_certified():
    # the conclusion's point beyond k_H(60) = 5.977: the window is the kink's echo, 5e-6
    r = run_point(Params(k=6, tau=60, delta=1e-6), SolverSettings(t_end=1e4))
    assert r.summary.attractor == "unstable-fixed-point"
    c = r.certificate
    assert not c.certified
    assert c.text.startswith("leading root +1.76e-07/t > 0")
    assert r.as_record()["certified"] is False


def test_a_blow_up_is_not_certified():
    # Fig. 7 (a = 0.035, k = 12, tau = 0.2): Euler leaves its stability region at t = 0.5
    p = Params(a=0.035, k=12, tau=0.2)
    tr = simulate(p, SolverSettings(t_end=100))
    assert tr.blew_up
    c = certify(tr, classify(tr.window_t, tr.window, tr.blew_up, None, tr.mid_t, tr.mid, p))
    assert not c.certified and c.text == f"blew up at t = {tr.t_blowup:.6g}"
    # the run re-integrated by the stiff scheme rests on the fast branch: no linear theory
    # of that state here, so not certified either
    r = run_point(p, SolverSettings(t_end=100))
    assert r.summary.attractor == "fast-branch"
    assert not r.certificate.certified and "fast-branch" in r.certificate.text


def test_an_orbit_other_than_the_runs_is_not_certified_for_it():
    """Euler at tau = 0.5, k = 37.6 (dt 1e-3) rides a cycle of amplitude 0.79 where the
    model's (RK4 at dt 1e-4: 0.496; Newton's from the run's final state: 0.4957) is 0.50:
    the run is not certified with the model's orbit, nor relabelled by it, and carries no
    multipliers or slips of it (its own dt_error flags it dt-sensitive). Before, it read
    "certified yes" with the RK4 orbit's period in place of its own."""
    r = run_point(Params(k=37.6, tau=0.5), SolverSettings(t_end=3000.0, lyap=False))
    rec = r.as_record()
    assert not r.certificate.certified and not r.certificate.scheme_off
    assert "is not the window's (amplitude 0.78" in r.certificate.text
    # tried again at dt / 4: the certifier's orbit is the same (amplitude 0.4955, 0.4958)
    assert "refined: at dt 0.01 found another orbit" in r.certificate.text
    assert "the certifier's orbit is the same at both steps" in r.certificate.text
    assert rec["multipliers"] == [] and rec["slips"] == 0
    assert "dt-sensitive" in r.summary.flags and "(certified)" not in r.summary.detail
    ref = run_point(Params(k=37.6, tau=0.5), SolverSettings(method="rk4", dt=1e-4,
                                                            t_end=300.0, window=100.0,
                                                            lyap=False))
    assert abs(rec["amplitude"] / ref.summary.amplitude - 1) > 0.5  # Euler's own error


def test_a_mismatch_the_certifiers_own_step_makes_is_refined_away():
    """At b = 24, k = 12, tau = 7.43 (sharp slips) RK4 at the certifier's dt 0.01 gives an
    amplitude of 10.237 where RK4 at dt 1e-3 gives 9.771 and the run's Euler 9.773: the
    certificate is tried again at dt / 4, where the orbit is the window's, and certified
    there, saying so; the run is not flagged dt-sensitive for the certifier's error (before,
    it was not certified: "is not the window's")."""
    p = Params(k=12.0, tau=7.43157894736842, b=24.0)
    r = run_point(p, SolverSettings(t_end=2e4, lyap=False))
    ref = run_point(p, SolverSettings(method="rk4", dt=1e-3, t_end=2e4, lyap=False))
    assert abs(r.summary.amplitude / ref.summary.amplitude - 1) < 1e-3
    c = r.certificate
    assert c.certified, c.text
    # tau / 2975 = 0.002497, refined from tau / 744 = 0.009989 (Grid.of's whole steps)
    assert "(RK4 at dt 0.002497, refined: at dt 0.009989 " in c.text
    assert abs(c.amplitude / ref.summary.amplitude - 1) < 1e-3
    orbit = find_orbit(p, dt=0.001)                          # an independent, finer orbit
    assert c.period == pytest.approx(orbit.period, rel=1e-6)
    assert c.slips == 1 and r.summary.maxima_per_period == 1
    assert "dt-sensitive" not in r.summary.flags


def test_a_period_the_certifiers_step_leaves_undecided_is_decided_at_a_finer_one():
    """b = 22, k = 12, tau = 2 (sharp slips): the window returns after 8 periods of 3.8024
    and Newton converges there at dt 0.01, where the shots over T / 8, T / 4, T / 2 miss by
    1.3e-4, 1.8e-4, 2.7e-5 of the amplitude (RK4's end interpolation, not the orbit). The
    certificate called it a period-30.419 orbit with 8 slips, and the run "complex"; at
    dt / 4 the misses fall 70 to 260 times and the orbit is certified at its period."""
    p = Params(k=12.0, tau=2.0, b=22.0)
    r = run_point(p, SolverSettings(t_end=2e4, lyap=False))
    c = r.certificate
    assert c.certified, c.text
    assert "refined: at dt 0.01 left its period undecided (shots over T / 8 to 1.3e-04" in c.text
    orbit = find_orbit(p, dt=0.001)                          # from its own simulation
    assert orbit.maxima_per_period == 1
    assert c.period == pytest.approx(orbit.period, rel=1e-6)  # measured 3.8023699, 3.8023700
    assert c.slips == 1
    s = r.summary
    assert (s.regime, s.period_count, s.maxima_per_period) == ("oscillatory", 1, 1), s.detail
    assert s.detail.startswith("period-1, 1 maximum")


def test_a_window_that_grows_where_theory_decays_is_not_a_certified_rest():
    """Next to the Hopf point (k = 6.145 < k_H(10) = 6.1462, root -1.0e-6 with the noise)
    Euler's O(dt) anti-damping makes the window grow (+8.9e-6/t): before, the certificate
    said "fixed point ... window decays at +8.881e-06/t"."""
    p = Params(k=6.145, tau=10.0, delta=1e-6)
    assert leading_exponent(p) < 0
    r = run_point(p, SolverSettings(t_end=2e4, lyap=False))
    assert not r.certificate.certified and "window grows" in r.certificate.text
    assert "dt-sensitive" in r.summary.flags
