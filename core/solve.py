"""Integrate one parameter point: settings, validation, and the call into a kernel.

Decisions the paper leaves open, made here:

* **History.** Eq. 19 fixes the five variables at t = 0 to delta but not m_x(t) for
  t < 0. By default we take the constant history m_x(t) = delta for t <= 0: it is the
  natural reading of "all variables start at delta", it is the state the system would
  hold had it rested there, and it makes the initial state a single point of the
  (m_x, history) space like the paper's offset suggests. Its slope (0) differs from
  m_y(0) = delta; the kink at t = 0 is carried to t = j tau. The history is a setting
  (``SolverSettings.history``): the one consistent with the initial velocity, or the
  final state of another run, are the others (core.history).
* **Grid.** Both schemes need tau = N dt (Euler reads m_x(t - tau) from a ring buffer of
  N slots; RK4 needs stage times on grid points). We take N = ceil(tau / dt) and the
  effective step dt' = tau / N <= dt. For tau on the paper's grids at dt = 1e-3 this is
  dt itself. With tau = 0 the delay term vanishes and dt is used as given.
* **Length.** n_steps = ceil(t_end / dt'); the run ends at n_steps dt' >= t_end.
"""

from __future__ import annotations

import math
import numbers
import time
from dataclasses import dataclass, field, replace
from typing import Literal

import numpy as np

from core.chunk_state import BLOWN, N_AT, ChunkState, plan_of, start_arrays
from core.classify import N_SUBWINDOWS
from core.closure import Realisability
from core.history import CarriedState, check_history
from core.history import start as history_start
from core.methods import METHOD_TABLE, METHODS, method
from core.params import ParameterError, Params, check_positive

Method = Literal["euler", "rk4", "stiff"]

#: When a run stops: "t_end", at its end time whatever it has become (the paper's
#: protocol); "certified", at the end of the first chunk after which its attractor is
#: certified from its own state (core.certified_stop), else at t_end as well.
STOPS: tuple[str, ...] = ("t_end", "certified")

#: Default step per method (core.methods.METHOD_TABLE). Euler: the paper's dt = 1e-3.
#: RK4: 1e-2, which costs about as much per time unit as Euler at 1e-3 and is ~1e6 times
#: more accurate. Stiff: 1e-3, first order like Euler, with errors against Radau about as
#: large or smaller; it stays stable at any step, and 1e-3 keeps the runs comparable with
#: Euler's (core.stiff).
DEFAULT_DT: dict[str, float] = {m.name: m.default_dt for m in METHOD_TABLE}
#: The paper's analysis window, [99000, 100000]: the default when the run is long enough
#: (see default_window).
DEFAULT_WINDOW = 1000.0

#: Spacing of the stored analysis window (time units). Peaks are refined with the quartic
#: through five samples (core.classify.find_peaks): at h = 0.01 its error was at most
#: ~5e-8 of the amplitude on the limit cycles we measured, under the 1e-6 return noise
#: floor of core.classify (the parabola through three samples reached 5e-6).
WINDOW_SAMPLE_DT = 0.01
#: At most this many stored window samples (a long window is sampled more coarsely).
MAX_WINDOW_SAMPLES = 1 << 20
#: A window to classify needs this many samples: core.classify splits it into
#: N_SUBWINDOWS sub-windows and measures an amplitude in each from 3 samples or more.
#: With fewer, a run of a single sample was labelled "sliding (at rest)" and a window of
#: a few samples stopped the classifier with a traceback.
MIN_WINDOW_SAMPLES = 3 * N_SUBWINDOWS

#: At most this many steps per run. The paper's run is 1e8 Euler steps (t = 1e5 at
#: dt = 1e-3); 1e10 is a hundred times that, and takes about 3 min of Euler with
#: lambda_max (17 ns a step) or 11 min of RK4 (66 ns) on the 2-core machine we measured
#: (benchmarks/bench_kernels.py measures others). Far beyond, a run holds a worker for
#: hours to years (t_end = 1e300 would never end), and the step counts must stay well
#: inside the kernels' 64-bit integers.
MAX_STEPS = 10**10
#: At most this much memory per run (bytes): 2 GiB, under the free memory of a laptop or
#: of a small cloud worker with a core or two, and some 200 times a paper run's needs (10
#: MB, mostly its two windows of 100 001 samples, at the middle and at the end; the delay
#: ring of tau = 10 at dt = 1e-3 is 160 kB). It counts what make_grid lays out
#: (memory_of): the delay ring, the window and trace samples and the lambda_max logs. It
#: is per run: a worker's batch (core.batch) holds the window, trace, logs and delay ring
#: of each of its runs at once (up to its --batch, default 64, cut to its --memory budget:
#: slopetui.queue.batch_memory), so a batch of runs near this limit needs many times it.
#: Such runs are rare (tau over 10^5 time units at dt = 1e-3, or more than 2.7e8
#: lambda_max renormalisations); a worker should then compute them with --batch 1.
MAX_RUN_BYTES = 2 * 1024**3
#: Bytes per delay step of the ring buffers: m_x for Euler and stiff, (m_x, m_y) for RK4
#: (core.methods: ring_rows), and as much again for the tangent, which the single-run
#: kernels carry even without lambda_max (core.chunk_state).
RING_BYTES: dict[str, int] = {m.name: 2 * m.ring_rows * 8 for m in METHOD_TABLE}
#: Bytes per window or trace sample: five variables and the sample's time.
SAMPLE_BYTES = 6 * 8
#: Bytes per lambda_max log: one float per tangent renormalisation.
LOG_BYTES = 8


class LimitError(ParameterError):
    """A setting the model allows but the engine refuses: more steps or memory than a run
    may take, or a window too short to classify. A stored spec that predates a limit is
    still read back (slopetui.sweeps.spec); its runs then fail with this message."""


def default_window(t_end: float) -> float:
    """The window when none is given: the paper's 1000, or half of a shorter run (so that
    ``t_end`` alone is never refused because of the default window)."""
    return min(DEFAULT_WINDOW, t_end / 2.0)


@dataclass(frozen=True, slots=True)
class SolverSettings:
    """How to integrate a point.

    method : "euler" (paper-faithful), "rk4" (4th order, Hermite delay) or "stiff"
             (linearly implicit, keeps the covariance realisable; core.stiff: what
             core.point falls back to where an explicit scheme blows up).
    dt     : step in model time units; None takes DEFAULT_DT[method].
    t_end  : end of the run (default 1e5, the paper's horizon).
    window : length of the analysis window at the end of the run; None takes
             min(1000, t_end / 2) (default_window: 1000 is the paper's [99000, 100000]).
             The settings keep the resolved value, so stored settings are explicit.
    lyap   : also compute lambda_max (tangent-linear co-integration).
    trace_points : size of the decimated whole-run trace kept for plots.
    history : m_x before t = 0 (core.history): "constant" (default, eq. 19's delta),
             "consistent" (delta (1 + t), no kink at t = 0) or "state:<digest>" (the
             final state of another run, given to simulate as ``carried``).
    stop   : when the run stops (STOPS): "t_end" (default, the paper's protocol) or
             "certified" (at the first chunk's end where its attractor is certified,
             t_end at the latest: core.certified_stop; core.point.run_point honours it).
             ``simulate`` itself always integrates to ``until`` or t_end.
    """

    method: str = "euler"
    dt: float | None = None
    t_end: float = 1e5
    window: float | None = None
    lyap: bool = True
    trace_points: int = 2000
    history: str = "constant"
    stop: str = "t_end"

    def __post_init__(self) -> None:
        check_history(self.history)
        if not isinstance(self.stop, str) or self.stop not in STOPS:
            raise ParameterError("stop", self.stop, "one of " + ", ".join(STOPS))
        if not isinstance(self.method, str) or self.method not in METHODS:
            raise ParameterError("method", self.method, "one of " + ", ".join(METHODS))
        if self.dt is not None:
            object.__setattr__(self, "dt", check_positive("dt", self.dt))
        object.__setattr__(self, "t_end", check_positive("t_end", self.t_end))
        if self.window is None:
            object.__setattr__(self, "window", default_window(self.t_end))
        object.__setattr__(self, "window", check_positive("window", self.window))
        if self.window > self.t_end:
            raise ParameterError("window", self.window, f"0 < window <= t_end = {self.t_end:g}")
        points = self.trace_points
        if (isinstance(points, bool) or not isinstance(points, numbers.Real)
                or not math.isfinite(points) or points != int(points) or points < 2):
            raise ParameterError("trace_points", points, "an integer >= 2")
        object.__setattr__(self, "trace_points", int(points))

    @property
    def step(self) -> float:
        """The requested step: dt, or the method's default."""
        return DEFAULT_DT[self.method] if self.dt is None else self.dt


@dataclass(frozen=True, slots=True)
class Grid:
    """The time grid a run uses: effective step, delay in steps, and the samplers.

    The window sampler takes ``n_mid`` samples from step ``mid_start`` (the window that
    ends at the middle of the run; n_mid = 0 when it would overlap the end window), then
    ``n_win`` from ``win_start`` (the analysis window at the end), every ``win_stride``
    steps, into one array: the kernels see it as one sampler that jumps once.
    """

    dt: float
    n_delay: int
    n_steps: int
    win_start: int
    win_stride: int
    n_win: int
    trace_stride: int
    n_trace: int
    renorm_steps: int
    mid_start: int = 0
    n_mid: int = 0

    @property
    def sample_start(self) -> int:
        """The window sampler's first step."""
        return self.mid_start if self.n_mid else self.win_start

    @property
    def n_samples(self) -> int:
        """The window sampler's columns: the middle window's, then the end window's."""
        return self.n_mid + self.n_win

    @property
    def sample_jump(self) -> int:
        """The column after which the sampler jumps to win_start (-1: no middle window)."""
        return self.n_mid if self.n_mid else -1

    def sample_steps(self) -> np.ndarray:
        """The steps at which the window sampler samples, in column order."""
        return np.concatenate((self.mid_start + self.win_stride * np.arange(self.n_mid),
                               self.win_start + self.win_stride * np.arange(self.n_win)))

    @property
    def t_end(self) -> float:
        return self.n_steps * self.dt

    def step_at(self, t: float) -> int:
        """The first step at or after model time t (n_steps at most), as n_steps is of
        t_end."""
        if not t < self.t_end:
            return self.n_steps
        return max(0, math.ceil(t / self.dt - 1e-9))

    @property
    def renorm_interval(self) -> float:
        return self.renorm_steps * self.dt


@dataclass(frozen=True, slots=True)
class Memory:
    """The bytes one run lays out, by part (see MAX_RUN_BYTES)."""

    ring: int    # delay history, with the tangent's
    window: int  # analysis window samples
    trace: int   # decimated trace samples
    logs: int    # lambda_max logs

    @property
    def total(self) -> int:
        return self.ring + self.window + self.trace + self.logs


def memory_of(g: Grid, s: SolverSettings) -> Memory:
    """The memory a run on grid ``g`` needs (single-run kernel; see MAX_RUN_BYTES)."""
    return Memory(ring=RING_BYTES[s.method] * (g.n_delay + 1), window=SAMPLE_BYTES * g.n_samples,
                  trace=SAMPLE_BYTES * g.n_trace,
                  logs=LOG_BYTES * (g.n_steps // g.renorm_steps) if s.lyap else 0)


def make_grid(p: Params, s: SolverSettings) -> Grid:
    """Validate the pair (p, s) and lay out the grid. Raises ParameterError (LimitError
    beyond MAX_STEPS or MAX_RUN_BYTES), before anything is allocated."""
    dt = s.step
    if p.tau > 0.0:
        if dt > p.tau:
            raise ParameterError("dt", dt, f"0 < dt <= tau = {p.tau:g}")
        # in floats first: tau / dt may be far beyond any ring we could hold, or infinite
        if RING_BYTES[s.method] * (p.tau / dt + 1.0) > MAX_RUN_BYTES:
            raise _ring_error(p, s, MAX_RUN_BYTES)
        n_delay = math.ceil(p.tau / dt - 1e-9)
        dt = p.tau / n_delay
    else:
        n_delay = 0
    if not s.t_end / dt <= MAX_STEPS:  # also an infinite ratio, before ceil() sees it
        raise _steps_error(p, s, dt)
    n_steps = max(1, math.ceil(s.t_end / dt - 1e-9))  # t_end far below dt: one step
    n_window_steps = min(n_steps, math.ceil(s.window / dt - 1e-9))
    win_stride = max(1, round(WINDOW_SAMPLE_DT / dt), math.ceil(n_window_steps / MAX_WINDOW_SAMPLES))
    n_win = n_window_steps // win_stride + 1
    win_start = n_steps - (n_win - 1) * win_stride
    # The middle window ends at the middle of the run; only if it fits before the end
    # window (a window of half the run or more has none: the classifier then compares the
    # halves of the end window).
    mid_start = n_steps // 2 - (n_win - 1) * win_stride
    n_mid = n_win if mid_start >= 0 and n_steps // 2 < win_start else 0
    trace_stride = max(1, n_steps // (s.trace_points - 1))
    n_trace = n_steps // trace_stride + 1
    renorm_steps = _renorm_steps(p, dt)
    g = Grid(dt, n_delay, n_steps, win_start, win_stride, n_win, trace_stride, n_trace,
             renorm_steps, mid_start if n_mid else 0, n_mid)
    _check_memory(p, s, g)
    return g


def _renorm_steps(p: Params, dt: float) -> int:
    """Steps between tangent renormalisations at the effective step dt."""
    # every tau time units, clamped to [1, 10]: long enough that the O(N) projection is
    # cheap per step, short enough that e^{lambda T_r} cannot overflow
    return max(1, round(min(max(p.tau, 1.0), 10.0) / dt))


def validate_run(p: Params, s: SolverSettings) -> Grid:
    """make_grid, and the window long enough to classify (MIN_WINDOW_SAMPLES): what a run
    that will be classified (``slopetui run``, a sweep) must pass. ``simulate`` alone
    accepts shorter windows: integrating needs no analysis."""
    g = make_grid(p, s)
    if g.n_win < MIN_WINDOW_SAMPLES:
        raise _window_error(s, g)
    return g


# -- the limits' messages: each names one field and its allowed range at the others ---

def _size(n: float) -> str:
    """Bytes in binary units, e.g. 21.8 TiB."""
    for unit in ("B", "KiB", "MiB", "GiB", "TiB", "PiB", "EiB"):
        if n < 1024.0 or unit == "EiB":
            return f"{n:.3g} {unit}"
        n /= 1024.0
    raise AssertionError("unreachable")


def _finer_dt_given(s: SolverSettings) -> bool:
    """Whether a limit on the steps or the ring is the fault of a dt chosen finer than the
    method's default (then dt is named; otherwise t_end or tau)."""
    return s.dt is not None and s.dt < DEFAULT_DT[s.method]


def _dt_floor(p: Params, s: SolverSettings) -> float:
    """The smallest dt within both MAX_STEPS and the ring's share of MAX_RUN_BYTES."""
    floor = s.t_end / MAX_STEPS
    if p.tau > 0.0:  # tau / dt + 1 slots of RING_BYTES
        floor = max(floor, p.tau / (MAX_RUN_BYTES / RING_BYTES[s.method] - 1.0))
    return floor


def _ring_error(p: Params, s: SolverSettings, budget: float) -> LimitError:
    slots = max(1, int(budget // RING_BYTES[s.method]) - 1)  # delay steps that fit
    need = RING_BYTES[s.method] * (p.tau / s.step + 1.0)
    cause = (f"the delay history holds tau / dt steps of {RING_BYTES[s.method]} bytes: "
             f"{_size(need)} of at most {_size(MAX_RUN_BYTES)} per run")
    if _finer_dt_given(s):
        low = max(p.tau / slots, _dt_floor(p, s))
        return LimitError("dt", s.step, f"dt >= {low:.3g} at tau = {p.tau:g}, "
                                        f"t_end = {s.t_end:g} ({cause})")
    return LimitError("tau", p.tau, f"0 <= tau <= {slots * s.step:.4g} at dt = {s.step:g} "
                                    f"({cause})")


def _steps_error(p: Params, s: SolverSettings, dt: float) -> LimitError:
    cause = f"at most {MAX_STEPS:.0e} steps per run".replace("e+", "e")
    if _finer_dt_given(s):
        return LimitError("dt", s.step, f"dt >= {_dt_floor(p, s):.3g} at tau = {p.tau:g}, "
                                        f"t_end = {s.t_end:g} ({cause})")
    high = MAX_STEPS * dt
    if s.lyap:  # the lambda_max logs may bind first (_check_memory)
        high = min(high, MAX_RUN_BYTES // LOG_BYTES * _renorm_steps(p, dt) * dt)
    return LimitError("t_end", s.t_end, f"0 < t_end <= {high:.4g} at dt = {dt:g} ({cause})")


def _check_memory(p: Params, s: SolverSettings, g: Grid) -> None:
    """Raise a LimitError naming the field of the largest part if the run needs more than
    MAX_RUN_BYTES; the range given leaves the other parts as they are."""
    m = memory_of(g, s)
    if m.total <= MAX_RUN_BYTES:
        return
    largest = max(("ring", m.ring), ("logs", m.logs), ("trace", m.trace), ("window", m.window),
                  key=lambda part: part[1])[0]
    budget = MAX_RUN_BYTES - (m.total - getattr(m, largest))
    cause = f"{_size(m.total)} of at most {_size(MAX_RUN_BYTES)} per run"
    if largest == "ring":
        raise _ring_error(p, s, budget)
    if largest == "logs":
        t_max = min(budget // LOG_BYTES * g.renorm_interval, MAX_STEPS * g.dt)
        raise LimitError("t_end", s.t_end,
                         f"0 < t_end <= {t_max:.4g} with lambda_max at dt = {g.dt:g}, "
                         f"tau = {p.tau:g} "
                         f"(one {LOG_BYTES}-byte log per renormalisation, every "
                         f"{g.renorm_interval:g} time units: {cause}), or no lambda_max")
    if largest == "trace":
        raise LimitError("trace_points", s.trace_points,
                         f"2 <= trace_points <= {budget // SAMPLE_BYTES - 1:.0f} ({cause})")
    raise LimitError("window", s.window, f"a shorter window ({cause})")  # at most ~50 MB


def _window_error(s: SolverSettings, g: Grid) -> LimitError:
    spacing = g.win_stride * g.dt
    needed = (MIN_WINDOW_SAMPLES - 1) * spacing
    cause = (f"the analysis window needs {MIN_WINDOW_SAMPLES} samples, 3 for each of the "
             f"classifier's {N_SUBWINDOWS} sub-windows, one every {spacing:.3g} time units")
    if needed <= s.t_end:
        return LimitError("window", s.window, f"{needed:.3g} <= window <= t_end = {s.t_end:g} "
                                              f"({cause}; by default the window is "
                                              f"min({DEFAULT_WINDOW:g}, t_end / 2))")
    # a step coarser than the sample spacing leaves fewer samples: a finer dt is the fix
    # if the run is long enough for a window sampled every WINDOW_SAMPLE_DT
    if (s.dt is not None and g.win_stride == 1
            and s.t_end >= (MIN_WINDOW_SAMPLES - 1) * WINDOW_SAMPLE_DT):
        return LimitError("dt", s.dt, f"dt <= {s.t_end / (MIN_WINDOW_SAMPLES - 1):.3g} at "
                                      f"t_end = {s.t_end:g} ({cause})")
    return LimitError("t_end", s.t_end, f"t_end >= {needed:.3g} at dt = {g.dt:g} ({cause})")


@dataclass(slots=True)
class Trajectory:
    """What one integration keeps. Arrays have rows (m_x, m_y, s_x, s_y, u): the analysis
    window at the end of the run, the window of as many samples that ends at its middle
    (empty when there is none, see Grid), and the trace of the whole run."""

    params: Params
    settings: SolverSettings
    grid: Grid
    steps_done: int
    window_t: np.ndarray
    window: np.ndarray
    trace_t: np.ndarray
    trace: np.ndarray
    lyap_logs: np.ndarray = field(repr=False)
    runtime_s: float = 0.0
    mid_t: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)
    mid: np.ndarray = field(default_factory=lambda: np.zeros((5, 0)), repr=False)
    #: The state at t_end to hand over (core.history.CarriedState); None after a blow-up,
    #: before t_end (a chunk: see ``chunk``) and from the batched kernels.
    final: CarriedState | None = field(default=None, repr=False)
    #: The carried state the run started from, if its history is one.
    carried: CarriedState | None = field(default=None, repr=False)
    #: The arrays the kernel wrote, whole: the window samples (5, Grid.n_samples: the
    #: middle window's, then the end window's), the trace (5, Grid.n_trace) and the
    #: lambda_max logs, of which the arrays above are views. A run of the same grid can be
    #: copied into them (moved_into): core.point.run_batch writes a lane's stiff
    #: re-integration there, so that a batch holds each lane's samples once.
    buffers: tuple[np.ndarray, np.ndarray, np.ndarray] | None = field(default=None, repr=False,
                                                                     compare=False)
    #: The running minima of s_x, s_y and s_x s_y - u^2 over every step, and the first
    #: violation (core.closure.Realisability); None where no kernel kept them.
    realisability: Realisability | None = None
    #: The whole state at steps_done of a run stopped before t_end (simulate's ``until``),
    #: from which ``simulate(..., resume=)`` continues it; None once the run is at t_end,
    #: after a blow-up and from the batched kernels.
    chunk: ChunkState | None = field(default=None, repr=False, compare=False)
    #: The kernel said it left the bounds (core.chunk_state: BLOWN), also at its last step.
    blown: bool = False

    @property
    def blew_up(self) -> bool:
        return self.blown or (self.steps_done < self.grid.n_steps and self.chunk is None)

    @property
    def t_done(self) -> float:
        """Model time the run has reached (t_end once it is whole)."""
        return self.steps_done * self.grid.dt

    @property
    def t_blowup(self) -> float | None:
        """Model time at which the run left the bounded region, or None."""
        return self.steps_done * self.grid.dt if self.blew_up else None


def simulate(p: Params, s: SolverSettings | None = None,
             carried: CarriedState | None = None, *, until: float | None = None,
             resume: Trajectory | None = None) -> Trajectory:
    """Integrate eqs. 6a-6e from the initial conditions of eq. 19 and the history of
    ``s.history`` (``carried``: the state that history names, when it names one).

    In chunks: ``until`` (model time) stops the run at the first step at or after it
    (t_end if later), with ``chunk`` set to continue from. ``resume``, such a chunk of the
    same (p, s), continues it, writing into its arrays (its own views stay as they were),
    to ``until`` or t_end. The chunks of a run end, bit for bit, where one call to the same
    time ends: its samples, lambda_max logs, minima, state and steps (the kernel contract,
    core.methods)."""
    from core.model import coefficients  # numba's (~0.3 s): loaded where a run is integrated

    s = s or SolverSettings()
    g = make_grid(p, s)
    m = method(s.method)
    if resume is None:
        buffers = (np.full((5, g.n_samples), np.nan), np.full((5, g.n_trace), np.nan),
                   np.zeros(g.n_steps // g.renorm_steps if s.lyap else 0))
        init, hx = history_start(p, g.dt, g.n_delay, s.history, carried)
        now, counts, ring, e_ring = start_arrays(m, g.n_delay, g.sample_start, g.renorm_steps,
                                                 init, hx)
        spent = 0.0
    else:
        state, buffers, carried = _resumable(p, s, resume)
        hx = history_start(p, g.dt, g.n_delay, s.history, carried)[1]
        now, counts, ring, e_ring = state.arrays()
        spent = resume.runtime_s
    end = g.n_steps if until is None else max(int(counts[N_AT]), min(g.n_steps, g.step_at(until)))
    plan = plan_of(end, g.sample_start, g.win_stride, g.sample_jump, g.win_start,
                   g.trace_stride, g.renorm_steps)
    win, trace, logs = buffers
    t0 = time.perf_counter()
    done = int(m.kernel()(coefficients(p), g.dt, g.n_delay, s.lyap, plan, hx, now, counts, ring,
                          e_ring, win, trace, logs))
    runtime = spent + time.perf_counter() - t0
    after = ChunkState(s.method, g.dt, g.n_delay, now, counts, ring, e_ring)
    blown = bool(counts[BLOWN] >= 0)
    tr = trajectory_of(p, s, g, done, win, trace, logs, runtime, after.realisability(),
                       blew_up=blown)
    return replace(tr, carried=carried, blown=blown,
                   final=after.carried(p.tau) if done == g.n_steps and not blown else None,
                   chunk=after if done < g.n_steps and not blown else None)


def _resumable(p: Params, s: SolverSettings, tr: Trajectory
               ) -> tuple[ChunkState, tuple[np.ndarray, np.ndarray, np.ndarray], CarriedState | None]:
    """The state, arrays and carried history to continue ``tr`` from, or ValueError."""
    if tr.chunk is None or tr.buffers is None:
        raise ValueError("only a run stopped before t_end (simulate's until) can be resumed")
    if tr.params != p or tr.settings != s:
        raise ValueError("a run is resumed with its own parameters and settings")
    return tr.chunk, tr.buffers, tr.carried


def trajectory_of(p: Params, s: SolverSettings, g: Grid, done: int, win: np.ndarray,
                  trace: np.ndarray, logs: np.ndarray, runtime: float,
                  realisability: Realisability | None = None,
                  blew_up: bool | None = None) -> Trajectory:
    """Wrap a kernel's outputs (done steps, samplers, tangent logs, the running minima of
    the covariance) as a Trajectory. ``blew_up`` None: the run blew up if it stopped
    before t_end (a batched kernel's, which runs every lane to t_end)."""
    trace_n = g.trace_stride * np.arange(g.n_trace)
    # after a blow-up at step `done`, only the states before it were sampled; a run
    # stopped at `done` sampled the state there
    if blew_up is None:
        blew_up = done < g.n_steps
    last = done - 1 if blew_up else done
    n_w = (_sampled(g.mid_start, g.win_stride, g.n_mid, last)
           + _sampled(g.win_start, g.win_stride, g.n_win, last))
    n_t = int(np.count_nonzero(trace_n <= last))
    n_r = done // g.renorm_steps if s.lyap else 0
    n_m = min(n_w, g.n_mid)  # the middle window's samples, then the end window's
    times = _sample_times(g)
    return Trajectory(p, s, g, done, times[n_m:n_w], win[:, n_m:n_w], trace_n[:n_t] * g.dt,
                      trace[:, :n_t], logs[:n_r], runtime, times[:n_m], win[:, :n_m],
                      buffers=(win, trace, logs), realisability=realisability)


def _sampled(start: int, stride: int, n: int, last: int) -> int:
    """How many of the n steps start, start + stride, ... are at most ``last``."""
    return 0 if last < start else min(n, (last - start) // stride + 1)


def window_times(start: int, stride: int, n: int, dt: float) -> np.ndarray:
    """The times of n samples every ``stride`` steps from step ``start``: the floats of
    _sample_times (the step, exact as a float, times dt), for one window."""
    steps = np.arange(n, dtype=np.int64)
    steps *= stride
    steps += start
    times = steps.astype(float)
    times *= dt
    return times


def _sample_times(g: Grid) -> np.ndarray:
    """The times of the window sampler's columns (Grid.sample_steps() * dt, the same
    floats), built in one array of floats a part at a time: its step indices whole, as
    integers beside the floats, were 2 more arrays of the window's length at once (16 MiB
    each at window 1e5, dt 1e-3), in every lane of a batch."""
    times = np.empty(g.n_samples)
    for first, start, n in ((0, g.mid_start, g.n_mid), (g.n_mid, g.win_start, g.n_win)):
        steps = np.arange(n, dtype=np.int64)
        steps *= g.win_stride
        steps += start
        times[first:first + n] = steps  # exact: steps < 2^53 (MAX_STEPS)
    times *= g.dt
    return times


def moved_into(tr: Trajectory, buffers: tuple[np.ndarray, np.ndarray, np.ndarray]) -> Trajectory:
    """``tr`` with its samples and logs copied into ``buffers`` (another run's
    Trajectory.buffers, on the same grid), which it then views instead of its own arrays:
    the same values (and tr's times), and tr's own sample arrays are freed once tr is
    dropped. What ``buffers`` held is overwritten, so the run they came from must be held
    nowhere else. ``tr`` itself when the buffers are its own or of another shape (another
    grid)."""
    win, trace, logs = buffers
    g = tr.grid
    if np.may_share_memory(win, tr.window) or win.shape != (5, g.n_samples) \
            or trace.shape != (5, g.n_trace) or len(logs) < len(tr.lyap_logs):
        return tr
    n_m, n_w, n_t, n_r = (tr.mid.shape[1], tr.mid.shape[1] + tr.window.shape[1],
                          tr.trace.shape[1], len(tr.lyap_logs))
    win[:, :n_m] = tr.mid
    win[:, n_m:n_w] = tr.window
    trace[:, :n_t] = tr.trace
    logs[:n_r] = tr.lyap_logs
    return replace(tr, window=win[:, n_m:n_w], mid=win[:, :n_m], trace=trace[:, :n_t],
                   lyap_logs=logs[:n_r], buffers=buffers)
