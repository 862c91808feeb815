"""The certified stop on the batched lanes (core.certified_stop.certified_batch, core.batch
.simulate_batch_asking): each run stops where the single kernel's run stops, with the same
certificate, and its records are the no-stop batch's, bit for bit."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from core import batch as cb
from core import certified_stop as cst
from core.batch import simulate_batch
from core.certified_stop import certified_batch, simulate_to_certificate
from core.params import Params
from core.solve import SolverSettings

#: 12 points of tau = 1 from a stable rest state (k = 0.5) to cycles: with chunks from 50
#: (FIRST_CHUNK patched) to t_end 400 they stop at 50, 100 and 200, and one (Euler's
#: k = 16.6) runs to t_end.
POINTS = [Params(k=float(k), tau=1.0, delta=0.1) for k in np.linspace(0.5, 30.0, 12)]


def settings(method: str) -> SolverSettings:
    return SolverSettings(method=method, dt=1e-3 if method == "euler" else 1e-2, t_end=400.0,
                          window=20.0, lyap=True, stop="certified")


@pytest.fixture(autouse=True)
def short_chunks(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(cst, "FIRST_CHUNK", 50.0)


def same(a: np.ndarray, b: np.ndarray) -> bool:
    return a.shape == b.shape and np.array_equal(a, b, equal_nan=True)


@pytest.mark.parametrize("method", ["euler", "rk4"])
def test_lanes_stop_where_single_runs_stop_with_the_batch_records(method: str) -> None:
    s = settings(method)
    lanes = certified_batch(POINTS, s)
    whole = simulate_batch(POINTS, replace(s, stop="t_end"))
    stops = set()
    for p, lane, full in zip(POINTS, lanes, whole, strict=True):
        single = simulate_to_certificate(p, s)
        tr = lane.trajectory
        stops.add(tr.t_done)
        # where and why: the single kernel's (its round-off differs from the lanes' only in
        # the tangent's norm: the same stop and the same certificate's words)
        assert tr.steps_done == single.trajectory.steps_done, p
        assert (lane.certificate is None) == (single.certificate is None), p
        if lane.certificate is not None and single.certificate is not None:
            assert lane.certificate.certified and single.certificate.certified
            assert lane.summary is not None and single.summary is not None
            assert lane.summary.attractor == single.summary.attractor, p
        np.testing.assert_allclose(tr.window, single.trajectory.window, rtol=1e-9, atol=1e-12)
        assert same(tr.window_t, single.trajectory.window_t)
        assert same(tr.mid_t, single.trajectory.mid_t)
        assert same(tr.trace_t, single.trajectory.trace_t)
        if tr.steps_done == full.steps_done:  # never certified: the no-stop run (the last
            assert lane.certificate is None  # lanes go on alone: the single kernel's round-off)
            for x, y in ((tr.window, full.window), (tr.mid, full.mid), (tr.trace, full.trace)):
                np.testing.assert_allclose(x, y, rtol=1e-9, atol=1e-12)
            assert same(tr.window_t, full.window_t) and same(tr.mid_t, full.mid_t)
            continue
        # stopped: its windows are a no-stop batch's run to its stop (the grid of that
        # length), its trace and logs the whole run's so far (bit for bit where the lanes
        # and the single kernel agree: test_runs_never_certified_are_the_no_stop_runs)
        short = simulate_batch(POINTS, replace(s, stop="t_end", t_end=tr.t_done))[POINTS.index(p)]
        assert same(tr.window_t, short.window_t) and same(tr.mid_t, short.mid_t)
        for x, y in ((tr.window, short.window), (tr.mid, short.mid),
                     (tr.lyap_logs, full.lyap_logs[:len(tr.lyap_logs)]),
                     (tr.trace, full.trace[:, :tr.trace.shape[1]])):
            np.testing.assert_allclose(x, y, rtol=1e-9, atol=1e-12)
        assert tr.final is not None and tr.chunk is not None
    assert len(stops) >= 3  # stops at several chunk ends, and (Euler) t_end


def test_a_stopped_lane_ends_in_the_single_runs_state() -> None:
    """The state a lane stops at (its ``final``, what another run may start from:
    core.history) is the single kernel's at the same step: Euler without lambda_max, where
    the lanes and the single kernel agree bit for bit."""
    s = replace(settings("euler"), lyap=False)
    stopped = [r for r in certified_batch(POINTS, s) if r.certificate is not None]
    assert len(stopped) >= 6
    for lane in stopped:
        single = simulate_to_certificate(lane.trajectory.params, s).trajectory
        a, b = lane.trajectory.final, single.final
        assert a is not None and b is not None
        assert single.steps_done == lane.trajectory.steps_done
        assert same(a.now, b.now) and same(a.m_x, b.m_x)


@pytest.mark.parametrize("alone_below", [cb.MIN_LANES, 1])
def test_runs_never_certified_are_the_no_stop_runs(alone_below: int,
                                                   monkeypatch: pytest.MonkeyPatch) -> None:
    """Euler without lambda_max (lanes and single kernel agree bit for bit): a run that no
    chunk certifies is the no-stop batch's, whether its lane ran to t_end (alone_below 1)
    or went on alone from a chunk end with the last few lanes (the default)."""
    monkeypatch.setattr(cb, "MIN_LANES", alone_below)
    s = replace(settings("euler"), lyap=False)
    lanes = certified_batch(POINTS, s)
    whole = simulate_batch(POINTS, replace(s, stop="t_end"))
    going = [(lane, full) for lane, full in zip(lanes, whole, strict=True) if lane.certificate is None]
    assert going
    for lane, p in zip(lanes, POINTS, strict=True):
        if lane.certificate is not None:
            short = simulate_batch(POINTS, replace(s, stop="t_end", t_end=lane.trajectory.t_done))
            here = short[POINTS.index(p)]
            assert same(lane.trajectory.window, here.window) and same(lane.trajectory.mid, here.mid)
    for lane, full in going:
        tr = lane.trajectory
        assert tr.steps_done == full.steps_done
        for x, y in ((tr.window, full.window), (tr.mid, full.mid), (tr.trace, full.trace),
                     (tr.window_t, full.window_t), (tr.mid_t, full.mid_t)):
            assert same(x, y), tr.params


def test_a_stopped_run_s_result_is_its_window_s_analysis() -> None:
    """run_batch keeps the summary the certificate was tried on rather than classifying the
    same window again: the records equal a fresh analysis's (but the runtime)."""
    from core.point import analyse, run_batch
    s = settings("euler")
    runs = certified_batch(POINTS, s)
    results = run_batch(POINTS, s)
    checked = 0
    for run, result in zip(runs, results, strict=True):
        if run.certificate is None:
            continue
        fresh = analyse(run.trajectory, 0.0, certificate=run.certificate).as_record()
        kept = result.as_record()
        fresh.pop("runtime_s")
        kept.pop("runtime_s")
        assert kept == fresh
        checked += 1
    assert checked >= 6
