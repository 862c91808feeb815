"""The batched kernels (core.batch) against the single-trajectory kernels they batch."""

from __future__ import annotations

import math

import numpy as np
import pytest

from core.batch import LANES, MIN_LANES, simulate_batch
from core.params import Params
from core.point import run_batch, run_point
from core.solve import SolverSettings, Trajectory, simulate

#: Lanes that differ in what matters to the batch: no delay, tau = dt and 2 dt (the
#: shortest ring buffers, RK4's special case), a tau off the dt grid (dt' < dt, more steps),
#: long delays, runs that blow up early (Fig. 7's low a), and one tau shared by more
#: points than a kernel call takes (LANES), with blow-ups among them, so that a group is
#: split into calls and lanes leave a call while others go on (their columns compacted).
#: Every tau has MIN_LANES points or more: a smaller group is computed by the single kernel.
SHARED_TAU = [Params(a=a, k=k, tau=1.0) for k in np.linspace(2.0, 30.0, 35) for a in (3.2, 0.035)]
POINTS = ([Params(k=k, tau=tau) for k in (5.0, 10.0, 19.0, 30.0)
           for tau in (0.0, 1.3636, 2.0, 10.0)]
          + [Params(k=k, tau=tau) for k in (5.0, 10.0, 19.0, 30.0) for tau in (0.01, 0.002, 0.001)]
          + [Params(b=b, k=12.0, tau=3.0) for b in (6.0, 12.0, 18.0, 24.0)] + SHARED_TAU)


def test_the_points_exercise_groups_calls_and_blow_up() -> None:
    assert len(SHARED_TAU) > LANES
    lanes = simulate_batch(SHARED_TAU, SolverSettings(t_end=50.0, window=10.0, lyap=False))
    assert any(tr.blew_up for tr in lanes), "no lane blows up: the leave-early path is not tested"
    first = [tr.blew_up for tr in lanes[:LANES]]  # the first call's lanes
    assert any(b and not all(first[i + 1:]) for i, b in enumerate(first)), \
        "a lane that blows up must leave a call in which later lanes go on"


#: How closely a batched RK4 lane follows its single-kernel run without lambda_max. The
#: batched loop is vectorised and LLVM fuses RK4's multiply-adds there (and in the loop's
#: scalar remainder) a little differently from the single kernel, so the last bits differ
#: (core.batch's docstring). Measured on POINTS to t = 300 at dt = 1e-3 (3e5 steps): at
#: most 1.4e-13 absolute (5.5e-13 relative to 1 + |x|) in the window, and the same
#: blow-up steps.
RK4_RTOL, RK4_ATOL = 1e-10, 1e-11


def assert_lanes_equal_single_runs(points: list[Params], s: SolverSettings
                                   ) -> list[Trajectory]:
    """Each lane of the batch equals its single-kernel run: Euler's bit for bit, RK4's to
    RK4_RTOL and RK4_ATOL with the same blow-up step; returns the lanes."""
    lanes = simulate_batch(points, s)
    for p, lane in zip(points, lanes, strict=True):
        single = simulate(p, s)
        assert lane.steps_done == single.steps_done, p
        assert np.array_equal(lane.window_t, single.window_t), p
        assert np.array_equal(lane.trace_t, single.trace_t), p
        if s.method == "euler":
            assert np.array_equal(lane.window, single.window), p
            assert np.array_equal(lane.trace, single.trace), p
        else:
            np.testing.assert_allclose(lane.window, single.window, rtol=RK4_RTOL, atol=RK4_ATOL)
            np.testing.assert_allclose(lane.trace, single.trace, rtol=RK4_RTOL, atol=RK4_ATOL)
    return lanes


@pytest.mark.parametrize("method", ["euler", "rk4"])
def test_lanes_equal_single_kernel(method: str) -> None:
    assert_lanes_equal_single_runs(POINTS, SolverSettings(method=method, dt=1e-3, t_end=300.0,
                                                          window=100.0, lyap=False))


@pytest.mark.parametrize("method", ["euler", "rk4"])
def test_blow_up_inside_the_window_keeps_the_samples_before_it(method: str) -> None:
    # The window is the whole run, so a sample is due every 10 steps up to the blow-up, and
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


def test_an_empty_batch_and_a_small_group() -> None:
    assert simulate_batch([], SolverSettings()) == []
    # fewer than MIN_LANES points of one tau are the single kernel's runs, with the carried
    # state only it hands over
    s = SolverSettings(t_end=20.0, window=5.0)
    (lane,) = simulate_batch([Params(tau=1.0)], s)
    assert np.array_equal(lane.window, simulate(Params(tau=1.0), s).window)
    assert lane.final is not None
    small = simulate_batch([Params(k=5.0 + i, tau=1.0) for i in range(MIN_LANES - 1)], s)
    assert all(lane.final is not None for lane in small)
    group = simulate_batch([Params(k=5.0 + i, tau=1.0) for i in range(MIN_LANES)], s)
    assert all(lane.final is None for lane in group), "a group of MIN_LANES is batched"
