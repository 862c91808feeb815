"""Integrate one parameter point: settings, validation, and the call into a kernel.

Decisions the paper leaves open, made here:

* **History.** Eq. 19 fixes the five variables at t = 0 to delta but not m_x(t) for
  t < 0. We take the constant history m_x(t) = delta for t <= 0: it is the natural
  reading of "all variables start at delta", it is the state the system would hold had
  it rested there, and it makes the initial state a single point of the (m_x, history)
  space like the paper's offset suggests. Its slope (0) differs from m_y(0) = delta; the
  kink at t = 0 is carried to t = j tau and only matters for convergence tests over the
  first few tau.
* **Grid.** Both schemes need tau = N dt (Euler reads m_x(t - tau) from a ring buffer of
  N slots; RK4 needs stage times on grid points). We take N = ceil(tau / dt) and the
  effective step dt' = tau / N <= dt. For tau on the paper's grids at dt = 1e-3 this is
  dt itself. With tau = 0 the delay term vanishes and dt is used as given.
* **Length.** n_steps = ceil(t_end / dt'); the run ends at n_steps dt' >= t_end.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from core.euler import euler
from core.model import coefficients
from core.params import ParameterError, Params, check_positive
from core.rk4 import rk4

Method = Literal["euler", "rk4"]
METHODS: tuple[str, ...] = ("euler", "rk4")

#: Default step per method. Euler: the paper's dt = 1e-3. RK4: 1e-2, which costs about
#: as much per time unit as Euler at 1e-3 and is ~1e6 times more accurate.
DEFAULT_DT: dict[str, float] = {"euler": 1e-3, "rk4": 1e-2}

#: Spacing of the stored analysis window (time units). Peaks are refined with the quartic
#: through five samples (core.classify.find_peaks): at h = 0.01 its error was at most
#: ~5e-8 of the amplitude on the limit cycles we measured, under the 1e-6 return noise
#: floor of core.classify (the parabola through three samples reached 5e-6).
WINDOW_SAMPLE_DT = 0.01
#: At most this many stored window samples (a long window is sampled more coarsely).
MAX_WINDOW_SAMPLES = 1 << 20


@dataclass(frozen=True, slots=True)
class SolverSettings:
    """How to integrate a point.

    method : "euler" (paper-faithful) or "rk4" (4th order, Hermite delay).
    dt     : step in model time units; None takes DEFAULT_DT[method].
    t_end  : end of the run (default 1e5, the paper's horizon).
    window : length of the analysis window at the end of the run (default 1000, the
             paper's [99000, 100000]).
    lyap   : also compute lambda_max (tangent-linear co-integration).
    trace_points : size of the decimated whole-run trace kept for plots.
    """

    method: str = "euler"
    dt: float | None = None
    t_end: float = 1e5
    window: float = 1000.0
    lyap: bool = True
    trace_points: int = 2000

    def __post_init__(self) -> None:
        if self.method not in METHODS:
            raise ParameterError("method", self.method, "one of " + ", ".join(METHODS))
        if self.dt is not None:
            object.__setattr__(self, "dt", check_positive("dt", self.dt))
        object.__setattr__(self, "t_end", check_positive("t_end", self.t_end))
        object.__setattr__(self, "window", check_positive("window", self.window))
        if self.window > self.t_end:
            raise ParameterError("window", self.window, f"0 < window <= t_end = {self.t_end:g}")
        if int(self.trace_points) < 2:
            raise ParameterError("trace_points", self.trace_points, "an integer >= 2")

    @property
    def step(self) -> float:
        """The requested step: dt, or the method's default."""
        return DEFAULT_DT[self.method] if self.dt is None else self.dt


@dataclass(frozen=True, slots=True)
class Grid:
    """The time grid a run uses: effective step, delay in steps, and the samplers."""

    dt: float
    n_delay: int
    n_steps: int
    win_start: int
    win_stride: int
    n_win: int
    trace_stride: int
    n_trace: int
    renorm_steps: int

    @property
    def t_end(self) -> float:
        return self.n_steps * self.dt

    @property
    def renorm_interval(self) -> float:
        return self.renorm_steps * self.dt


def make_grid(p: Params, s: SolverSettings) -> Grid:
    """Validate the pair (p, s) and lay out the grid. Raises ParameterError."""
    dt = s.step
    if p.tau > 0.0:
        if dt > p.tau:
            raise ParameterError("dt", dt, f"0 < dt <= tau = {p.tau:g}")
        n_delay = math.ceil(p.tau / dt - 1e-9)
        dt = p.tau / n_delay
    else:
        n_delay = 0
    n_steps = math.ceil(s.t_end / dt - 1e-9)
    n_window_steps = min(n_steps, math.ceil(s.window / dt - 1e-9))
    win_stride = max(1, round(WINDOW_SAMPLE_DT / dt), math.ceil(n_window_steps / MAX_WINDOW_SAMPLES))
    n_win = n_window_steps // win_stride + 1
    win_start = n_steps - (n_win - 1) * win_stride
    trace_stride = max(1, n_steps // (int(s.trace_points) - 1))
    n_trace = n_steps // trace_stride + 1
    # renormalise the tangent every tau time units, clamped to [1, 10]: long enough that
    # the O(N) projection is cheap per step, short enough that e^{lambda T_r} cannot overflow
    renorm_steps = max(1, round(min(max(p.tau, 1.0), 10.0) / dt))
    return Grid(dt, n_delay, n_steps, win_start, win_stride, n_win, trace_stride, n_trace, renorm_steps)


@dataclass(slots=True)
class Trajectory:
    """What one integration keeps. Arrays have rows (m_x, m_y, s_x, s_y, u)."""

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

    @property
    def blew_up(self) -> bool:
        return self.steps_done < self.grid.n_steps

    @property
    def t_blowup(self) -> float | None:
        """Model time at which the run left the bounded region, or None."""
        return self.steps_done * self.grid.dt if self.blew_up else None


KERNELS = {"euler": euler, "rk4": rk4}


def simulate(p: Params, s: SolverSettings | None = None) -> Trajectory:
    """Integrate eqs. 6a-6e from the initial conditions of eq. 19."""
    s = s or SolverSettings()
    g = make_grid(p, s)
    win = np.full((5, g.n_win), np.nan)
    trace = np.full((5, g.n_trace), np.nan)
    logs = np.zeros(g.n_steps // g.renorm_steps if s.lyap else 0)
    t0 = time.perf_counter()
    done = KERNELS[s.method](
        coefficients(p), g.dt, g.n_delay, g.n_steps,
        win, g.win_start, g.win_stride, trace, g.trace_stride,
        s.lyap, g.renorm_steps, logs,
    )
    return trajectory_of(p, s, g, int(done), win, trace, logs, time.perf_counter() - t0)


def trajectory_of(p: Params, s: SolverSettings, g: Grid, done: int, win: np.ndarray,
                  trace: np.ndarray, logs: np.ndarray, runtime: float) -> Trajectory:
    """Wrap a kernel's outputs (done steps, samplers, tangent logs) as a Trajectory."""
    win_n = g.win_start + g.win_stride * np.arange(g.n_win)
    trace_n = g.trace_stride * np.arange(g.n_trace)
    # after a blow-up at step `done`, only the states before it were sampled
    last = g.n_steps if done == g.n_steps else done - 1
    n_w, n_t = int(np.count_nonzero(win_n <= last)), int(np.count_nonzero(trace_n <= last))
    n_r = done // g.renorm_steps if s.lyap else 0
    return Trajectory(p, s, g, done, win_n[:n_w] * g.dt, win[:, :n_w], trace_n[:n_t] * g.dt,
                      trace[:, :n_t], logs[:n_r], runtime)
