"""A run integrated in chunks is the run integrated in one call, bit for bit (the kernel
contract, core.methods, item 6): samples of both windows and the trace, lambda_max's
logs, the realisability minima and first violation, the steps, and the state handed over."""

from __future__ import annotations

import numpy as np
import pytest

from core.batch import batch, batch_steps, start_batch
from core.chunk_state import ChunkState
from core.methods import METHOD_TABLE, METHODS
from core.model import coefficients
from core.params import Params
from core.solve import Grid, SolverSettings, Trajectory, make_grid, simulate

#: (k, tau, delta): the defaults' neighbourhood, a small delay where Euler's s_y goes
#: negative at once (a first violation to carry over), no delay, and a slow start.
POINTS = [(10.0, 10.0, 0.1), (6.0, 0.2, 0.1), (12.0, 0.0, 0.1), (20.0, 1.0, 1e-3)]
#: Chunk ends (model time): inside the middle window ([50, 100]) and at its end, on a
#: renormalisation (every tau, clamped to [1, 10]) and a sample (every 0.01), one step
#: after another chunk's end, and t = 0 (no step at all).
UNTIL = (0.0, 37.3, 40.0, 40.001, 100.0, 150.5)


def settings(method: str) -> SolverSettings:
    return SolverSettings(method=method, t_end=200.0, window=50.0, lyap=True, trace_points=500)


def in_chunks(p: Params, s: SolverSettings, until: tuple[float, ...]) -> Trajectory:
    tr = simulate(p, s, until=until[0])
    for t in until[1:]:
        tr = simulate(p, s, until=t, resume=tr)
    return simulate(p, s, resume=tr)


def assert_same(a: Trajectory, b: Trajectory) -> None:
    """Equal to the bit (NaN where neither sampled)."""
    assert a.steps_done == b.steps_done and a.blew_up == b.blew_up
    for x, y in ((a.window_t, b.window_t), (a.window, b.window), (a.mid_t, b.mid_t),
                 (a.mid, b.mid), (a.trace_t, b.trace_t), (a.trace, b.trace),
                 (a.lyap_logs, b.lyap_logs)):
        assert x.shape == y.shape
        assert np.array_equal(x, y, equal_nan=True)
    assert a.realisability == b.realisability
    assert (a.final is None) == (b.final is None)
    if a.final is not None and b.final is not None:
        assert np.array_equal(a.final.now, b.final.now) and np.array_equal(a.final.m_x, b.final.m_x)


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize(("k", "tau", "delta"), POINTS)
def test_chunks_equal_one_call(method: str, k: float, tau: float, delta: float) -> None:
    p, s = Params(k=k, tau=tau, delta=delta), settings(method)
    whole = simulate(p, s)
    chunked = in_chunks(p, s, UNTIL)
    assert_same(chunked, whole)
    assert chunked.chunk is None and not chunked.blew_up
    assert whole.mid.shape[1] > 0 and whole.lyap_logs.size > 0  # both windows, lambda_max


def test_violation_and_minima_carried_over() -> None:
    """Euler's s_y goes below 0 right after the start at delta = 0.1 (core.stiff): the
    first violation is found in the first chunk and kept through the later ones, and the
    minima of later chunks are merged in."""
    p, s = Params(k=6.0, tau=0.2, delta=0.1), settings("euler")
    first = simulate(p, s, until=1.0)
    assert first.realisability is not None and first.realisability.t_first is not None
    assert first.realisability.t_first < 1.0
    whole = simulate(p, s)
    assert in_chunks(p, s, (1.0,)).realisability == whole.realisability


def test_a_chunk_is_the_run_so_far() -> None:
    """A chunk to t holds what the run to t sampled so far, and its state at t."""
    p, s = Params(k=10.0, tau=10.0), settings("rk4")
    part = simulate(p, s, until=120.0)
    assert part.chunk is not None and part.chunk.step == part.steps_done
    assert part.t_done == pytest.approx(120.0) and not part.blew_up and part.final is None
    whole = simulate(p, s)
    n = part.trace.shape[1]
    assert np.array_equal(part.trace, whole.trace[:, :n])
    assert np.array_equal(part.mid, whole.mid)  # the middle window ends at t = 100
    assert part.window.shape[1] == 0              # the end window starts at t = 150
    assert np.array_equal(part.lyap_logs, whole.lyap_logs[:part.lyap_logs.size])
    assert part.chunk.now[1] == part.trace[1, -1]  # the trace's last sample is at t = 120


def test_resuming_leaves_the_chunk_alone() -> None:
    """A ChunkState is read-only, and continuing from it does not change it: the same
    chunk continued twice gives the same run."""
    p, s = Params(k=10.0, tau=10.0), settings("euler")
    part = simulate(p, s, until=60.0)
    assert isinstance(part.chunk, ChunkState) and not part.chunk.now.flags.writeable
    before = part.chunk.now.copy(), part.chunk.ring.copy()
    a = simulate(p, s, until=80.0, resume=part)
    assert np.array_equal(part.chunk.now, before[0]) and np.array_equal(part.chunk.ring, before[1])
    b = simulate(p, s, until=80.0, resume=part)
    assert np.array_equal(a.trace, b.trace) and np.array_equal(a.lyap_logs, b.lyap_logs)


def test_blow_up_inside_a_chunk() -> None:
    """Fig. 7's fast branch (a = 0.035, k = 12, tau = 1): Euler blows up at t ~ 0.5
    (core.stiff). Continued from a chunk before it, at the same step as in one call, and
    nothing to continue from after it."""
    p, s = Params(a=0.035, k=12.0, tau=1.0), SolverSettings(method="euler", t_end=10.0,
                                                               window=5.0, lyap=True)
    whole = simulate(p, s)
    assert whole.blew_up
    chunked = simulate(p, s, resume=simulate(p, s, until=0.2))
    assert_same(chunked, whole)
    assert chunked.chunk is None and chunked.final is None


def test_resume_refuses_what_it_cannot_continue() -> None:
    p, s = Params(k=10.0, tau=10.0), settings("euler")
    with pytest.raises(ValueError, match="stopped before t_end"):
        simulate(p, s, resume=simulate(p, replace_t_end(s, 20.0)))
    part = simulate(p, s, until=10.0)
    with pytest.raises(ValueError, match="own parameters"):
        simulate(Params(k=11.0, tau=10.0), s, resume=part)


def replace_t_end(s: SolverSettings, t_end: float) -> SolverSettings:
    return SolverSettings(method=s.method, t_end=t_end, window=t_end / 2, lyap=s.lyap)


def test_registry_names_every_kernel() -> None:
    """Each registered method's kernel and tangent kernel load, and the command line's
    choices are the registry's names."""
    for m in METHOD_TABLE:
        assert callable(m.kernel())
        assert m.tangents() is None or callable(m.tangents())
        assert "core.methods" in (m.kernel().__doc__ or "")  # points to the contract
    assert tuple(m.name for m in METHOD_TABLE) == METHODS


def test_blow_up_at_the_last_step() -> None:
    """A run that leaves the bounds at its very last step blew up: no state to hand over
    and no sample of the state beyond the bound (the step count alone cannot tell it from a
    run that ended in bounds)."""
    p = Params(a=0.035, k=12.0, tau=1.0)
    probe = simulate(p, SolverSettings(method="euler", t_end=10.0, window=5.0, lyap=False))
    assert probe.blew_up
    last = probe.steps_done * probe.grid.dt  # the run that ends on that step
    s = SolverSettings(method="euler", t_end=last, window=last / 2, lyap=False)
    tr = simulate(p, s)
    assert tr.steps_done == tr.grid.n_steps == probe.steps_done
    assert tr.blew_up and tr.final is None and tr.t_blowup == pytest.approx(last)
    assert np.all(np.isfinite(tr.trace)) and np.all(np.abs(tr.trace[1]) < 1e6)


@pytest.mark.parametrize("method", ["euler", "rk4"])
def test_chunks_from_a_carried_history(method: str) -> None:
    """A warm start (core.history: the final state of another run) continues in chunks as
    in one call: RK4 reads the carried history at half steps for its first delay, across
    a chunk's end here (tau = 10, chunk at t = 4.5)."""
    p = Params(k=10.0, tau=10.0)
    first = simulate(p, SolverSettings(method=method, t_end=50.0, window=25.0, lyap=False))
    assert first.final is not None
    s = SolverSettings(method=method, t_end=60.0, window=20.0, lyap=True,
                       history=first.final.name)
    whole = simulate(p, s, first.final)
    chunked = simulate(p, s, resume=simulate(p, s, first.final, until=4.5))
    assert_same(chunked, whole)
    assert chunked.carried is first.final


def batch_outputs(g: Grid, lanes: int) -> tuple[np.ndarray, ...]:
    """A batch's (win, trace, logs, done, lows, cross), as core.batch._integrate lays them out."""
    return (np.full((lanes, g.n_samples, 5), np.nan), np.full((lanes, g.n_trace, 5), np.nan),
            np.zeros((lanes, g.n_steps // g.renorm_steps)), np.zeros(lanes, dtype=np.int64),
            np.zeros((lanes, 3)), np.full(lanes, -1, dtype=np.int64))


@pytest.mark.parametrize("method", ["euler", "rk4"])
def test_batched_kernel_resumes(method: str) -> None:
    """The batched kernel continued from its state (start_batch, batch_steps) at the chunk
    ends of UNTIL gives every lane what one call gives, bit for bit: samples, logs, steps,
    minima; the chunk in which the minima first crossed may end earlier (a chunk end)."""
    s = settings(method)
    points = [Params(k=k, tau=10.0, delta=0.1) for k in np.linspace(6.0, 20.0, 8)]
    g = make_grid(points[0], s)
    coef = np.stack([coefficients(p) for p in points])
    sampler = np.array([g.sample_start, g.win_stride, g.sample_jump, g.win_start], dtype=np.int64)
    rk4 = method == "rk4"
    one = batch_outputs(g, len(points))
    batch(rk4, coef, g.dt, g.n_delay, g.n_steps, sampler, g.trace_stride, True, g.renorm_steps,
          *one)
    chunked = batch_outputs(g, len(points))
    state = start_batch(rk4, coef, g.n_delay, sampler, g.trace_stride, True, g.renorm_steps,
                        chunked[0], chunked[1])
    for t in (*UNTIL, s.t_end):
        batch_steps(rk4, g.dt, g.n_delay, g.n_steps, g.step_at(t), True, g.renorm_steps, *state,
                    *chunked)
    for a, b in zip(chunked[:5], one[:5], strict=True):
        assert np.array_equal(a, b, equal_nan=True)
    assert np.all(one[3] == g.n_steps)
    assert np.all((chunked[5] <= one[5]) & ((chunked[5] >= 0) == (one[5] >= 0)))
