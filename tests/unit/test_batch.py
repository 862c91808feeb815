"""The batched kernels (core.batch) against the single-trajectory kernels they batch."""

from __future__ import annotations

import math

import numpy as np
import pytest

from core import Params, SolverSettings, Trajectory, run_batch, run_point, simulate
from core.batch import LANES, simulate_batch

#: Lanes that differ in what matters to the batch: no delay, tau = dt and 2 dt (the
#: shortest ring buffers, RK4's special case), a tau off the dt grid (dt' < dt, more steps),
#: long delays, a run that blows up early (Fig. 7's low a), and more lanes than slots, so
#: slots are refilled and, at the end, compacted.
POINTS = ([Params(k=k, tau=tau) for k in (5.0, 10.0, 19.0, 30.0)
           for tau in (0.0, 1.3636, 2.0, 10.0)]
          + [Params(k=10.0, tau=0.01), Params(k=10.0, tau=0.002), Params(k=10.0, tau=0.001),
             Params(a=0.035, k=10.0, tau=1.0), Params(b=24.0, k=12.0, tau=3.0)])


def test_the_points_exercise_refill_and_blow_up() -> None:
    assert len(POINTS) > LANES
    blown = [tr for tr in simulate_batch(POINTS, SolverSettings(t_end=50.0, window=10.0,
                                                                 lyap=False)) if tr.blew_up]
    assert blown, "no lane blows up: the leave-early path is not tested"


def assert_lanes_equal_single_runs(points: list[Params], s: SolverSettings
                                   ) -> list[Trajectory]:
    """Each lane of the batch equals its single-kernel run bit for bit; returns the lanes."""
    lanes = simulate_batch(points, s)
    for p, lane in zip(points, lanes, strict=True):
        single = simulate(p, s)
        assert lane.steps_done == single.steps_done, p
        assert np.array_equal(lane.window, single.window), p
        assert np.array_equal(lane.window_t, single.window_t), p
        assert np.array_equal(lane.trace, single.trace), p
    return lanes


@pytest.mark.parametrize("method", ["euler", "rk4"])
def test_lanes_equal_single_kernel_bit_for_bit(method: str) -> None:
    assert_lanes_equal_single_runs(POINTS, SolverSettings(method=method, dt=1e-3, t_end=300.0,
                                                          window=100.0, lyap=False))


@pytest.mark.parametrize("method", ["euler", "rk4"])
def test_blow_up_inside_the_window_keeps_the_samples_before_it(method: str) -> None:
    # The window is the whole run, so the blocks sample every step up to the blow-up, and
    # the lane's window must end where the single kernel's did.
    dt = 1e-3 if method == "euler" else 1e-2  # RK4 at 1e-3 does not blow up at low a
    s = SolverSettings(method=method, dt=dt, t_end=50.0, window=50.0, lyap=False)
    lanes = assert_lanes_equal_single_runs([p for p in POINTS if p.tau == 0.0 or p.tau >= dt],
                                           s)
    assert any(lane.blew_up and lane.window.shape[1] > 1 for lane in lanes)


@pytest.mark.parametrize("method", ["euler", "rk4"])
def test_lanes_with_lambda_equal_single_kernel_to_rounding(method: str) -> None:
    s = SolverSettings(method=method, dt=1e-3, t_end=300.0, window=100.0, lyap=True)
    for p, lane in zip(POINTS, simulate_batch(POINTS, s), strict=True):
        single = simulate(p, s)
        assert lane.steps_done == single.steps_done, p
        assert lane.lyap_logs.shape == single.lyap_logs.shape, p
        if not single.blew_up:
            np.testing.assert_allclose(lane.window, single.window, rtol=1e-9, atol=1e-12)
            np.testing.assert_allclose(lane.lyap_logs, single.lyap_logs, rtol=0, atol=1e-9)


def test_run_batch_gives_the_records_of_run_point() -> None:
    s = SolverSettings(t_end=2000.0, window=500.0)
    points = [Params(k=5.0, tau=2.0), Params(k=10.0, tau=2.0), Params(k=19.0, tau=2.0),
              Params(a=0.035, k=10.0, tau=1.0)]
    for batched, single in zip(run_batch(points, s), [run_point(p, s) for p in points],
                               strict=True):
        a, b = batched.as_record(), single.as_record()
        assert a["regime"] == b["regime"]
        assert a["t_blowup"] == b["t_blowup"]
        if not math.isnan(b["lambda_max"]):
            assert a["lambda_max"] == pytest.approx(b["lambda_max"], abs=1e-9)
        assert a["runtime_s"] > 0


def test_an_empty_batch_and_a_single_lane() -> None:
    assert simulate_batch([], SolverSettings()) == []
    s = SolverSettings(t_end=20.0, window=5.0)
    (lane,) = simulate_batch([Params(tau=1.0)], s)
    assert np.array_equal(lane.window, simulate(Params(tau=1.0), s).window)
