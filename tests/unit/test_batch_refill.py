"""core.batch with stops: lanes retired after a chunk, refilled with the batch's waiting
points, padded when none waits; every run's record is its run's in a batch without stops,
up to where it stopped, bit for bit."""

from __future__ import annotations

import numpy as np
import pytest

from core import batch as cb
from core.batch import VECTOR, _Lanes, chunk_steps, simulate_batch
from core.params import Params
from core.solve import SolverSettings, Trajectory, make_grid

#: 20 points of one tau on 8 lanes: more points than lanes, so lanes are refilled.
POINTS = [Params(k=float(k), tau=1.0, delta=0.1) for k in np.linspace(4.0, 30.0, 20)]
#: t_end is not a whole number of chunks (5 time units here): lanes that reach it wait
#: for the chunk's end to take a point, and a batch whose lanes all ended skips ahead.
T_END = 42.0


def settings(method: str) -> SolverSettings:
    return SolverSettings(method=method, t_end=T_END, window=10.0, lyap=True, trace_points=50)


def same_run(a: Trajectory, b: Trajectory) -> None:
    """Bit for bit: steps, samples and their times, logs, minima; the state, if both have one."""
    assert a.steps_done == b.steps_done
    for x, y in ((a.window, b.window), (a.window_t, b.window_t), (a.mid, b.mid),
                 (a.mid_t, b.mid_t), (a.trace, b.trace), (a.trace_t, b.trace_t),
                 (a.lyap_logs, b.lyap_logs)):
        assert x.shape == y.shape
        assert np.array_equal(x, y, equal_nan=True)
    assert a.realisability == b.realisability
    assert a.blew_up == b.blew_up is False
    if a.chunk is not None and b.chunk is not None:
        for x, y in zip((a.chunk.now, a.chunk.counts, a.chunk.ring, a.chunk.e_ring),
                        (b.chunk.now, b.chunk.counts, b.chunk.ring, b.chunk.e_ring), strict=True):
            assert np.array_equal(x, y)


@pytest.fixture(autouse=True)
def short_chunks(monkeypatch: pytest.MonkeyPatch) -> None:
    """Chunks of 5 time units (tau = 1: 5 renormalisation intervals), so that a run of 42
    has 8 chunk ends."""
    monkeypatch.setattr(cb, "CHUNK_T", 5.0)


@pytest.mark.parametrize("method", ["euler", "rk4"])
def test_retired_and_refilled_lanes_keep_their_runs(method: str) -> None:
    """Point i stops after its (i % 5)-th chunk (never, for 0: it runs to t_end); its record
    is the no-stop batch's (all 20 lanes started at step 0) at that step, bit for bit:
    samples, logs, minima and its state there. Those that run to t_end equal their whole
    no-stop run. RK4 tests the history read by a lane started late (fill_lane's patch)."""
    s = settings(method)
    g = make_grid(POINTS[0], s)
    c = chunk_steps(g)
    assert c == 5 * g.renorm_steps
    views: dict[tuple[int, int], Trajectory] = {}

    def record(tr: Trajectory) -> bool:
        views[(POINTS.index(tr.params), tr.steps_done)] = tr
        return False

    whole = _Lanes(g, POINTS, s).run(record)  # every lane from step 0, none stops
    for tr, alone in zip(whole, simulate_batch(POINTS, s), strict=True):
        same_run(tr, alone)
    stops = {i: (i % 5) * c for i in range(len(POINTS)) if i % 5}

    def finished(tr: Trajectory) -> bool:
        i = POINTS.index(tr.params)
        same_run(tr, views[(i, tr.steps_done)])  # the view so far, too
        return stops.get(i) == tr.steps_done

    lanes = _Lanes(g, POINTS, s, lanes=8)
    runs = lanes.run(finished)
    for i, (tr, ref) in enumerate(zip(runs, whole, strict=True)):
        if i in stops:
            assert tr.steps_done == stops[i] < g.n_steps
            same_run(tr, views[(i, stops[i])])
            assert tr.t_done == pytest.approx(stops[i] * g.dt)
        else:
            assert tr.steps_done == g.n_steps
            same_run(tr, ref)
    # the points start in order, 8 at step 0, the others later: at chunk ends (multiples of
    # c) or where a batch with no lane skipped to (a renormalisation step)
    assert [p for p, _ in lanes.starts] == list(range(len(POINTS)))
    assert [n for _, n in lanes.starts[:8]] == [0] * 8
    assert all(n > 0 and n % g.renorm_steps == 0 for _, n in lanes.starts[8:])
    assert [n for _, n in lanes.starts] == sorted(n for _, n in lanes.starts)


def test_a_retired_lane_takes_the_next_point_at_that_chunk_end() -> None:
    """Lane retired after the first chunk: the next waiting point starts at that step (c);
    two retired, two start; none waiting, the rest of the lanes are padding and the
    batch ends when its last lane does."""
    s = settings("euler")
    g = make_grid(POINTS[0], s)
    c = chunk_steps(g)
    points = POINTS[:10]
    lanes = _Lanes(g, points, s, lanes=8)
    runs = lanes.run(lambda tr: POINTS.index(tr.params) in (2, 5) and tr.steps_done == c)
    assert lanes.starts == [*((i, 0) for i in range(8)), (8, c), (9, c)]
    assert [tr.steps_done for tr in runs] == [g.n_steps if i not in (2, 5) else c for i in range(10)]


def test_padding_when_no_point_waits() -> None:
    """Of 8 points on 8 lanes, 5 retire at the first chunk end: the 3 left are computed in
    a whole vector (padded: copies of lane 0 in the 5 columns after them), and give their
    no-stop runs."""
    s = settings("rk4")
    g = make_grid(POINTS[0], s)
    c = chunk_steps(g)
    points = POINTS[:8]
    lanes = _Lanes(g, points, s, lanes=8)
    runs = lanes.run(lambda tr: POINTS.index(tr.params) >= 3 and tr.steps_done == c)
    assert lanes.at[cb.B_ACTIVE] == 0
    assert cb.padded(3, 8) == VECTOR and cb.padded(9, 16) == 2 * VECTOR and cb.padded(3, 4) == 4
    for tr, ref in zip(runs[:3], simulate_batch(points, s)[:3], strict=True):
        same_run(tr, ref)
    assert all(tr.steps_done == c for tr in runs[3:])


def test_pad_lanes_copies_lane_zero() -> None:
    """pad_lanes: the columns after the active ones up to a whole vector hold lane 0's state
    and ring (finite numbers, whatever left them)."""
    s = settings("euler")
    g = make_grid(POINTS[0], s)
    coef = np.stack([cb.coefficients(p) for p in POINTS[:8]])
    st, ring, e_ring, li, lane_of, at = cb.empty_batch(False, 8, g.n_delay, True, g.renorm_steps)
    template = cb.lane_template(np.zeros(4, dtype=np.int64), 1, 1, 1)
    for i in range(8):
        cb.fill_lane(i, coef[i], False, g.n_delay, st, ring, e_ring, li, lane_of, at, template)
    st[cb.M_Y * cb.LANES + 5] = np.nan  # a lane out of bounds leaves
    assert cb.drop_blown(8, 8, st, ring, e_ring, li, lane_of, np.zeros(8, dtype=np.int64)) == 7
    assert 5 not in lane_of[:7] and lane_of[5] == 7
    at[cb.B_ACTIVE] = cb.remove_lane(6, 7, 8, st, ring, e_ring, li, lane_of)
    for c in (6, 7):
        assert all(st[r * cb.LANES + c] == st[r * cb.LANES] for r in range(cb.N_ROWS))
        assert np.array_equal(ring[c::8], ring[0::8])


def test_without_stops_every_lane_runs_to_t_end_on_fewer_lanes() -> None:
    """No predicate: 20 points on 8 lanes run in turns, each its whole no-stop run."""
    s = settings("euler")
    g = make_grid(POINTS[0], s)
    for tr, ref in zip(_Lanes(g, POINTS, s, lanes=8).run(None), simulate_batch(POINTS, s),
                       strict=True):
        same_run(tr, ref)


def test_simulate_batch_stops_small_groups_too() -> None:
    """simulate_batch with ``finished``: a group of fewer than MIN_LANES points runs on the
    single kernel in the same chunks, and stops where it says."""
    s = settings("euler")
    g = make_grid(POINTS[0], s)
    c = chunk_steps(g)
    p = Params(k=7.0, tau=3.0)
    (alone,) = simulate_batch([p], s, finished=lambda tr: tr.steps_done >= 2 * c)
    assert alone.steps_done == 2 * chunk_steps(make_grid(p, s))
    assert not alone.blew_up
    lanes = simulate_batch(POINTS, s, finished=lambda tr: tr.steps_done >= 3 * c)
    assert [tr.steps_done for tr in lanes] == [3 * c] * len(POINTS)
