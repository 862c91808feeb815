"""The certified stop at the paper's settings (Euler, dt 1e-3, t_end 1e5, lambda_max):
runs stopped at their certificate agree with the paper's protocol on regime and attractor
over the (k, tau) plane, and their lambda_max (the certificate's) with independent
references: the leading root of linear theory and the long run's Lyapunov spectrum."""

from __future__ import annotations

import math

import pytest

from core.params import Params
from core.point import run_point
from core.solve import SolverSettings
from core.spectrum import spectrum
from core.stability import leading_exponent

pytestmark = pytest.mark.computation  # only computes: beside the slow tiers (tests/xdist_plan.py)

PAPER = SolverSettings()
CERTIFIED = SolverSettings(stop="certified")


@pytest.mark.parametrize(("k", "tau"), [(0.5, 0.5), (4.0, 10.0), (3.0, 20.0), (10.0, 10.0),
                                        (15.0, 5.0), (20.0, 10.0), (25.0, 0.5)])
def test_the_certified_stop_keeps_the_papers_labels_across_the_plane(k, tau):
    """Stable rest states and cycles stop at the first chunk (1562.5 of 1e5); k = 20,
    tau = 10 (a multi-slip transient Newton cannot reach within its budget) runs to t_end
    with the paper's run's record."""
    p = Params(k=k, tau=tau)
    long, short = (run_point(p, s).as_record() for s in (PAPER, CERTIFIED))
    assert (short["regime"], short["attractor"]) == (long["regime"], long["attractor"])
    if short["certified"]:
        assert float(short["t_stop"]) <= 1e5 / 16  # type: ignore[arg-type]
        assert long["certified"], long["certificate"]
    else:
        assert short["t_stop"] == long["t_stop"] == 1e5
        assert short["lambda_max"] == long["lambda_max"] and short["period"] == long["period"]


def test_a_fixed_points_lambda_max_is_the_root_the_paper_run_measures():
    """k = 4, tau = 10: the certified lambda_max is linear theory's root; the paper's run
    (5e4 time units averaged) measures the Euler map's, within its error and Euler's O(dt)
    bias (0.2-1.7 % in sliding runs: core.lyapunov_bias)."""
    p = Params(k=4.0, tau=10.0)
    long, short = (run_point(p, s).as_record() for s in (PAPER, CERTIFIED))
    root = leading_exponent(p)
    assert short["lambda_max"] == pytest.approx(root, rel=1e-9)
    gap = abs(float(long["lambda_max"]) - root)  # type: ignore[arg-type]
    assert gap <= 3 * float(long["lambda_err"]) + 0.017 * abs(root)  # type: ignore[arg-type]


def test_an_orbits_next_exponent_is_the_long_runs_second_lyapunov_exponent():
    """k = tau = 10: the certified orbit's next exponent log|mu_2|/T (Floquet multipliers
    of RK4's orbit, Newton from the run's state at its stop) against the second exponent of
    the Lyapunov spectrum of a run to 2e4 (Euler's tangent map, m_x shift quotiented out:
    core.spectrum), an independent method: -0.04202 against -0.04214(14)."""
    p = Params(k=10.0, tau=10.0)
    short = run_point(p, CERTIFIED).as_record()
    assert short["certified"] and short["lambda_max"] == 0.0
    mu2 = max(math.hypot(*m) for m in short["multipliers"])  # type: ignore[union-attr]
    nxt = math.log(mu2) / float(short["period"])  # type: ignore[arg-type]
    ref = spectrum(p, SolverSettings(t_end=2e4), 2)
    assert abs(ref.values[0]) <= 3 * ref.errors[0]  # the flow's 0
    assert abs(nxt - ref.values[1]) <= max(3 * ref.errors[1], 0.01 * abs(nxt))
