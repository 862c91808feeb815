"""A run that stops where its attractor is certified (``SolverSettings.stop = "certified"``).

**Chunks.** The run integrates in chunks that end at n_J = n_steps, n_(j-1) = n_j // 2
(steps), the first ending at FIRST_CHUNK time units or later and holding a whole analysis
window. After each chunk the window that ends there (the last ``window`` time units, sampled
as the paper's run samples its end window) is classified (core.classify) and, where it can
succeed, the certificate is tried (core.certify): a fixed point by its leading root and the
window's decay, an orbit by Newton from the run's state and its multipliers. The run stops at
the first chunk whose certificate holds; otherwise it goes on, and at t_end it is the paper's
run.

**Why halving.** The window that ends at n_j / 2 is the previous chunk's window, so each
chunk's classification has its middle window (``settled``) as the paper's run has, at no
cost; and a run that is never certified has, at t_end, the paper's end and middle windows,
trace, lambda_max logs and state bit for bit (the kernels continue a chunk's state exactly:
core.chunk_state), so its result is the t_end run's. A chunk's window samples only inside the
chunk: each chunk after the first is at least as long as the first, which holds a window.

**The analysis window** of a stopped run is the last ``window`` time units before its stop,
its middle window the one ending at half of it, its trace the whole run's (decimated for
t_end: the stopped part of it is coarser), its final state the state it stopped at.

**The cost of trying.** A try classifies a window (its samples: 1e5 at the paper's window)
and certifies only a window classified ``fixed-point`` or a settled ``periodic`` one: others
cannot succeed (core.certify refuses them), and a periodic window that is not settled has
not reached its orbit (Newton from it would spend its whole budget: benchmarks/
bench_certified_stop.py measures what the tries cost).
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from core.certify import Certificate, certify
from core.chunk_state import BLOWN, I_W, NEXT_W, ChunkState, plan_of, start_arrays
from core.classify import Summary, classify
from core.history import CarriedState
from core.history import start as history_start
from core.lyapunov import LyapunovEstimate, estimate
from core.methods import method
from core.params import Params
from core.solve import Grid, SolverSettings, Trajectory, make_grid, trajectory_of, window_times

#: The first chunk ends at this time or later (the first n_steps // 2^j at or past it):
#: the paper's window of 1000 must fit in it, and the stable rest states decay below
#: round-off by t ~ 1100 at the median leading root of the (k, tau) plane at delta = 0.1.
FIRST_CHUNK = 1000.0
#: A certified fixed point stops the run only once the window ends this close to linear:
#: the nonlinear friction terms of eq. 6b, |q| h^2 + a h^3 at the half peak-to-peak h of
#: m_y over the window's last tenth, at most this share of the linear one, F' h. The
#: certificate's decay check (core.certify: the window's rate within 10 % of the root)
#: measures linearity over the whole window; this bounds it where the run stops. At the
#: defaults (F' = 3.456, q = -6.24) it admits a peak-to-peak of 0.011: k = 5.5, tau = 10,
#: delta = 0.1 (bistable: delta = 0.5 reaches the cycle) decays at the root's rate with
#: 0.0146 at t = 1562.5 and stops at 3125; every run of an 8 x 8 (k, tau) plane and 15 runs
#: around the subcritical Hopf point at tau = 10 (k 2-6.14, delta 0.1-1) kept the t_end
#: run's regime and attractor.
LINEAR_SHARE = 0.01


@dataclass(frozen=True, slots=True)
class Stopped:
    """A run integrated under the certified stop: its trajectory (at its stop, or t_end),
    and where it stopped early, the certificate and the window's summary that stopped it."""

    trajectory: Trajectory
    certificate: Certificate | None = None
    summary: Summary | None = None
    #: The chunks integrated and the certificates tried (for the benchmarks and the tests).
    chunks: int = 0
    tries: int = 0
    #: CPU seconds spent classifying and certifying the chunks before the last.
    try_s: float = 0.0


def chunk_ends(p: Params, s: SolverSettings, g: Grid) -> list[tuple[int, Grid]]:
    """The chunks' last steps, each with the grid of a run of that length (its windows:
    the end window, and its middle window, which is the previous chunk's). The last is
    (g.n_steps, g). A chunk whose grid would lay out its window otherwise than the run's
    (a grid whose rounding differs) ends the halving there."""
    ends = [(g.n_steps, g)]
    window_steps = (g.n_win - 1) * g.win_stride
    while True:
        n = ends[-1][0] // 2
        if n * g.dt < FIRST_CHUNK or n < window_steps or n * g.dt < s.window:
            break
        part = make_grid(p, replace(s, t_end=n * g.dt))
        if (part.n_steps, part.dt, part.win_stride, part.n_win) != (n, g.dt, g.win_stride, g.n_win):
            break
        ends.append((n, part))
    return ends[::-1]


def simulate_to_certificate(p: Params, s: SolverSettings, carried: CarriedState | None = None,
                            resume: Trajectory | None = None) -> Stopped:
    """Integrate (p, s) in chunks, stopping at the first whose attractor is certified (the
    module docstring); t_end at the latest. ``resume``: the run at one of its chunk ends
    that did not stop there (a batch's lane: core.batch hands its last few lanes to the
    single kernel), continued from its state and buffers at the next chunk (its runtime
    then this continuation's)."""
    from core.model import coefficients  # numba's: loaded where a run is integrated

    g = make_grid(p, s)
    m = method(s.method)
    kernel, coef = m.kernel(), coefficients(p)
    ends = chunk_ends(p, s, g)
    first = ends[0][1]
    init, hx = history_start(p, g.dt, g.n_delay, s.history, carried)
    windows: dict[int, np.ndarray] = {}  # each chunk's end window, by its last step
    first_win = np.zeros((5, 0))
    if resume is None:
        start = 0
        now, counts, ring, e_ring = start_arrays(m, g.n_delay, first.sample_start,
                                                 g.renorm_steps, init, hx)
        trace = np.full((5, g.n_trace), np.nan)
        logs = np.zeros(g.n_steps // g.renorm_steps if s.lyap else 0)
    else:
        c, buffers = resume.chunk, resume.buffers
        if c is None or buffers is None or resume.steps_done not in dict(ends[:-1]):
            raise ValueError("only a run at one of its chunk ends (chunk_ends) is resumed")
        start = 1 + [end for end, _ in ends].index(resume.steps_done)
        now, counts, ring, e_ring = c.now.copy(), c.counts.copy(), c.ring.copy(), c.e_ring.copy()
        trace, logs = np.ascontiguousarray(buffers[1]), buffers[2].copy()  # the kernel's layout
        windows[resume.steps_done] = resume.window.copy()
    runtime = try_s = 0.0
    tries = 0
    for j, (end, part) in enumerate(ends[start:], start):
        if j == 0:  # its middle window too, if it has one: the sampler of a run to `end`
            win = first_win = np.full((5, part.n_samples), np.nan)
            plan = plan_of(end, part.sample_start, part.win_stride, part.sample_jump,
                           part.win_start, g.trace_stride, g.renorm_steps)
        else:  # the end window only: its middle window is the previous chunk's
            win = np.full((5, part.n_win), np.nan)
            plan = plan_of(end, part.win_start, part.win_stride, -1, 0, g.trace_stride,
                           g.renorm_steps)
            counts[NEXT_W], counts[I_W] = part.win_start, 0
        t0 = time.perf_counter()
        done = int(kernel(coef, g.dt, g.n_delay, s.lyap, plan, hx, now, counts, ring, e_ring,
                          win, trace, logs))
        runtime += time.perf_counter() - t0
        windows[end] = win[:, part.n_mid:] if j == 0 else win
        if j == 0 and part.n_mid:  # the first chunk's own middle window, for _stopped
            windows[end // 2] = win[:, :part.n_mid]
        blown = bool(counts[BLOWN] >= 0)
        state = ChunkState(s.method, g.dt, g.n_delay, now.copy(), counts.copy(), ring.copy(),
                           e_ring.copy())
        if blown or end == g.n_steps:
            tr = _whole(p, s, g, ends, windows, first_win, done, trace, logs, runtime, state, blown)
            return Stopped(replace(tr, carried=carried), chunks=j + 1, tries=tries, try_s=try_s)
        c0 = time.process_time()
        tr = _stopped(p, s, g, part, windows, end, trace, logs, runtime, state, carried)
        summary, cert = attempt(tr)
        try_s += time.process_time() - c0
        tries += cert is not None
        if cert is not None and cert.certified and near_linear(tr, summary):
            return Stopped(tr, cert, summary, chunks=j + 1, tries=tries, try_s=try_s)
    raise AssertionError("unreachable: the last chunk ends at t_end")


def certified_batch(points: Sequence[Params], s: SolverSettings) -> list[Stopped]:
    """The points integrated as simulate_to_certificate integrates each, on the batched
    lanes (core.batch.simulate_batch_asking): the same chunk ends, the same question at
    each (attempt, near_linear), a lane that is certified retiring there. Each run stops
    where simulate_to_certificate's stops, with its certificate; its records are the same
    to round-off (bit for bit where the lanes and the single kernel agree: Euler without
    lambda_max; the tangent's norm sums in another order: tests/unit/test_certified_batch.py).
    Its runtime_s is its share of the batch's kernel time plus its own tries."""
    from core.batch import simulate_batch_asking  # numba's: loaded where runs are integrated

    def ask(tr: Trajectory) -> tuple[Certificate, Summary] | None:
        summary, cert = attempt(tr)
        if cert is not None and cert.certified and near_linear(tr, summary):
            return cert, summary
        return None

    def alone(p: Params, at: Trajectory | None) -> tuple[Trajectory, tuple[Certificate, Summary] | None]:
        run = simulate_to_certificate(p, s, resume=at)
        if run.certificate is None or run.summary is None:
            return run.trajectory, None
        return run.trajectory, (run.certificate, run.summary)

    runs = simulate_batch_asking(points, s, lambda p, g: chunk_ends(p, s, g), ask, alone)
    return [Stopped(tr, *found) if found is not None else Stopped(tr) for tr, found in runs]


def attempt(tr: Trajectory) -> tuple[Summary, Certificate | None]:
    """The chunk's window classified, and its certificate where it can succeed (None: not
    tried; the module docstring says which)."""
    lyap = estimate(tr.lyap_logs, tr.grid.renorm_interval) if tr.settings.lyap else None
    summary = classify(tr.window_t, tr.window, False, lyap, tr.mid_t, tr.mid, tr.params)
    if summary.attractor == "fixed-point" or (summary.attractor == "periodic" and summary.settled):
        return summary, certify(tr, summary)
    return summary, None


def near_linear(tr: Trajectory, summary: Summary) -> bool:
    """Whether the window ends where eq. 6b is linear to LINEAR_SHARE (a fixed point; an
    orbit's certificate needs no such bound)."""
    if summary.attractor != "fixed-point":
        return True
    p = tr.params
    tail = tr.window[1, -max(2, tr.window.shape[1] // 10):]
    h = 0.5 * float(np.ptp(tail))
    return abs(p.q) * h + p.a * h * h <= LINEAR_SHARE * abs(p.F1)  # divided by h


def _stopped(p: Params, s: SolverSettings, g: Grid, part: Grid, windows: dict[int, np.ndarray],
             end: int, trace: np.ndarray, logs: np.ndarray, runtime: float, state: ChunkState,
             carried: CarriedState | None) -> Trajectory:
    """The run stopped at step ``end`` (a chunk's): its window, its middle window (the
    previous chunk's, where a run to ``end`` has one), the trace and logs so far, its state."""
    win = windows[end]
    mid_t, mid = np.zeros(0), np.zeros((5, 0))
    if part.n_mid:
        mid_t, mid = window_times(part.mid_start, part.win_stride, part.n_mid, g.dt), windows[end // 2]
    n_t = end // g.trace_stride + 1
    n_r = end // g.renorm_steps if s.lyap else 0
    return Trajectory(p, s, g, end, window_times(part.win_start, part.win_stride, part.n_win, g.dt), win,
                      g.trace_stride * np.arange(n_t) * g.dt, trace[:, :n_t], logs[:n_r], runtime,
                      mid_t, mid, final=state.carried(p.tau), carried=carried,
                      realisability=state.realisability(), chunk=state)


def _whole(p: Params, s: SolverSettings, g: Grid, ends: list[tuple[int, Grid]],
           windows: dict[int, np.ndarray], first: np.ndarray, done: int, trace: np.ndarray, logs: np.ndarray,
           runtime: float, state: ChunkState, blown: bool) -> Trajectory:
    """The run at t_end, or where it blew up: the paper's run's trajectory (core.solve
    .simulate's), its middle and end windows taken from the chunks that sampled them
    (``first``: the first chunk's samples, its own middle window's too)."""
    win = np.full((5, g.n_samples), np.nan)
    if g.n_mid and g.n_steps // 2 in windows:
        win[:, :g.n_mid] = windows[g.n_steps // 2]
    if g.n_steps in windows:
        win[:, g.n_mid:] = windows[g.n_steps]
    if len(ends) == 1:  # one chunk: its sampler was the run's own
        win = first
    tr = trajectory_of(p, s, g, done, win, trace, logs, runtime, state.realisability(),
                       blew_up=blown)
    at_end = done == g.n_steps and not blown
    return replace(tr, blown=blown, final=state.carried(p.tau) if at_end else None)


def certified_lambda(p: Params, cert: Certificate) -> tuple[LyapunovEstimate, str] | None:
    """lambda_max from a certificate, with the words that say where it comes from: a fixed
    point's leading root (linear theory), an orbit's 0 along the flow with the next exponent
    log|mu_2| / T from its leading nontrivial multiplier. These are the continuous model's
    (an orbit's multipliers RK4's at core.certify's step); the paper's Euler map's exponent
    differs from them by its O(dt) bias (core.lyapunov_bias). None: nothing certified."""
    if not cert.certified:
        return None
    if math.isfinite(cert.root):  # a float, as the estimates from the logs are
        return (LyapunovEstimate(float(cert.root), 0.0, 0.0, 0),
                f"lambda_max {cert.root:+.6g}/t: the leading root (linear theory, the "
                "continuous model's; the run's map differs by its O(dt) bias)")
    if math.isfinite(cert.period) and cert.multipliers:
        mu2 = max(abs(m) for m in cert.multipliers)
        nxt = math.log(mu2) / cert.period
        return (LyapunovEstimate(0.0, 0.0, 0.0, 0),
                f"lambda_max 0 along the flow (a stable orbit), the next exponent "
                f"log|mu_2|/T = {nxt:+.6g}/t (|mu_2| = {mu2:.6f}, T = {cert.period:.8g})")
    return None
