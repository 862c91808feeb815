"""The accuracy of a run's scheme at its step: a shadow integration at half the step.

The paper's Euler at dt = 1e-3 is first order, and where the orbit turns fast (small tau,
large k, omega ~ 8) its cycles come out tens of per cent too large while the label looks
right: at tau = 0.5, k = 37.6 (just past the Hopf point k_H = 37.40, where Euler's
anti-damping moves the onset) Euler's peak-to-peak m_y is 0.790, RK4's (dt = 1e-3, 1e-4
agree to 1e-7) 0.496. Nothing in the window shows it; a second integration does.

**The estimate.** From the run's own final state (the five variables and m_x over the last
delay: core.chunk_state.ChunkState.carried, or the window's samples for a batched run), the run's
scheme integrates a span S twice: at the run's step dt and at dt / 2 (its history given at
the half steps by core.history.half_steps, 4th order). The dt shadow continues the run's
attractor; the dt / 2 shadow relaxes from it to the finer scheme's. Over the second half
of the span both give an amplitude (refined maxima minus refined minima of m_y,
core.classify.find_peaks: 4e-8 of the amplitude), a period (whole returns of the major
maxima) and a label (at rest, or how many distinct heights the major maxima have; a
continuum). Richardson's extrapolation with the scheme's order p (Euler and the stiff
scheme 1, RK4 4) gives the error of the dt run:

    E_Q = (Q_dt - Q_dt/2) 2^p / (2^p - 1),     Q_ref = Q_dt - E_Q,

and ``dt_error`` is max(|E_A| / |A_ref|, |E_T| / |T_ref|) over those of amplitude A and
period T that exist. The flag ``dt-sensitive``: dt_error above 1 % (the issue's tolerance)
or a label that differs between the two shadows.

**At rest** the estimate is NaN, on purpose: a rest state of eqs. 6a-6e is a fixed point of
each scheme's map too (Euler, RK4 and the stiff scheme step a zero right-hand side to
itself), so the rest level carries no discretisation error at any dt. What the scheme does
change there is the decay rate, λmax's bias against the continuous root, which
core.lyapunov_bias reports beside λmax. A blown-up run has no state to start from (NaN).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace

import numpy as np

from core.classify import AMPLITUDE_FLOOR, Summary, find_peaks, maxima_words
from core.history import CarriedState, half_steps
from core.methods import method
from core.params import Params
from core.solve import SolverSettings, Trajectory, simulate

#: Above this relative change of amplitude or period the run is flagged dt-sensitive: the
#: issue's 1 %.
TOLERANCE = 0.01
#: The shadow's span, in time units: twice SPAN_RETURNS of the run's period (1 / its
#: dominant frequency for a continuum), at least MIN_SPAN and at most the run's window
#: (what its label rests on): the analysis takes the second half, SPAN_RETURNS returns.
#: At the paper's settings the estimate then costs at most 3 x 1000 / 1e5 of the run's
#: steps (the dt / 2 shadow twice the dt one). The dt / 2 shadow relaxes from the dt
#: attractor at the orbit's slowest Floquet rate; its maxima at t = 100 were still off
#: their limit by 2.7 % of the difference the estimate measures at tau = 0.5, k = 37.6
#: (0.5 % past the Hopf point), 0.9 % at k = tau = 10 and 0.2 % at k = 20, tau = 10
#: (Euler; 0.1 %, 0.02 %, 0.08 % at t = 200): the estimate over [100, 200] is good to a
#: few per cent of itself.
MIN_SPAN = 200.0
SPAN_RETURNS = 10.0
#: The span doubles (continuing both shadows) until the dt / 2 shadow's amplitude changes
#: between the last two quarters of the span by at most RELAXED of the difference it
#: measures (or by RELAXED_FLOOR of itself), at most MAX_DOUBLINGS times; the estimate of
#: a shadow still relaxing is a lower bound, and says so. The span stays within
#: MAX_WINDOWS windows: at tau = 60, k = 20 (slips per delay still changing, Fig. 3's
#: "torus", never relaxed) spans of four windows cost 21 % of a paper-settings run, of
#: two 8.7 %.
RELAXED = 0.1
RELAXED_FLOOR = 1e-5
MAX_DOUBLINGS = 2
MAX_WINDOWS = 2.0
#: Maxima whose heights differ by more than this fraction of the amplitude are distinct
#: (the shadows' label). Euler's two maxima at k = 20, tau = 10 differ by 0.2 % of the
#: amplitude and drift (a slow modulation: core.classify): one height here, in both
#: shadows alike.
LABEL_GAP = 0.01
#: The periods of a return's maxima, each over the same returns, may differ by this much
#: (relative) before the shadow's period counts as undefined: an orbit whose slips are
#: still spreading out (the multi-slip states are long transients, docs/numerics.md). At
#: k = 16, tau = 20 (Euler, t_end 2e4) the dt / 2 shadow's two maxima returned after 20.407
#: and 20.327 (4e-3 apart), the dt shadow's after 20.406 and 20.406 (5e-5); one maximum
#: alone had made a period error of 0.7 % of it, where RK4's and Euler's periods agree to
#: 2e-6. Settled orbits return alike to 1e-8 (k = tau = 10, two maxima).
DRIFT = 1e-3
#: The attractors at rest (core.classify): the estimate is NaN there (module docstring).
AT_REST = ("fixed-point", "unstable-fixed-point", "fast-branch", "variance-state", "divergent")


@dataclass(frozen=True, slots=True)
class DtError:
    """The estimated error of a run's scheme at its step (relative; NaN: not estimated).

    amplitude, period: the Richardson estimates E / Q_ref of each (signed: positive when
    the run's value is too large), NaN where the quantity does not exist. labels: the
    label of the dt shadow, then of the dt / 2 shadow (_measures). reason: why the
    estimate is NaN, or what it rests on."""

    value: float
    amplitude: float = math.nan
    period: float = math.nan
    labels: tuple[str, str] = ("", "")
    span: float = 0.0
    relaxed: bool = True
    reason: str = ""
    cost_s: float = 0.0

    @property
    def label_changed(self) -> bool:
        return self.labels[0] != self.labels[1]

    @property
    def sensitive(self) -> bool:
        """The run's amplitude, period or label would change by more than TOLERANCE."""
        return (math.isfinite(self.value) and self.value > TOLERANCE) or self.label_changed

    def _changes(self) -> str:
        """The changes measured: amplitude, period, label."""
        parts = [f"{name} {v:+.2g}" for name, v in (("amplitude", self.amplitude),
                                                      ("period", self.period)) if math.isfinite(v)]
        if self.label_changed:
            parts.append(f"label {self.labels[0]} -> {self.labels[1]}")
        return ", ".join(parts)

    def text(self) -> str:
        """One line for ``slopetui run``."""
        if not math.isfinite(self.value):
            return f"not estimated ({self.reason})"
        return (f"{self.value:.2g}  ({self._changes()}; {self.reason})"
                + ("; dt-sensitive" if self.sensitive else ""))


def dt_error(tr: Trajectory, summary: Summary) -> DtError:
    """The error estimate of run ``tr`` (classified as ``summary``): see the module
    docstring."""
    t0 = time.process_time()
    if tr.blew_up:
        return DtError(math.nan, reason="the run blew up: no state to start from")
    if summary.attractor in AT_REST:
        return DtError(math.nan, reason="at rest: a rest state is each scheme's own at any "
                                        "dt; the decay's bias is lambda_max's")
    start = start_of(tr)
    if start is None:
        return DtError(math.nan, reason="the window is shorter than the delay")
    p, s, dt = tr.params, tr.settings, tr.grid.dt
    span = shadow_span(summary, s)
    coarse, fine = shadow(p, s.method, dt, start, span), shadow(p, s.method, dt / 2, finer(start), span)
    if coarse.blew_up or fine.blew_up:  # from the run's own state: a label of its own
        labels = tuple("unstable, divergent" if x.blew_up else "bounded" for x in (coarse, fine))
        return DtError(math.nan, labels=(labels[0], labels[1]), span=span,
                       reason=f"the {'dt' if coarse.blew_up else 'dt/2'} shadow blew up",
                       cost_s=time.process_time() - t0)
    continuum = summary.period_count < 0
    relaxed = continuum or _relaxed(coarse, fine)
    for _ in range(MAX_DOUBLINGS):
        if (relaxed or coarse.final is None or fine.final is None
                or 2 * coarse.window_t[-1] > MAX_WINDOWS * max(s.window, MIN_SPAN)):
            break
        more = coarse.window_t[-1]
        c_more = shadow(p, s.method, dt, coarse.final, more)
        f_more = shadow(p, s.method, dt / 2, fine.final, more)
        if c_more.blew_up or f_more.blew_up:  # keep the spans measured before
            break
        coarse, fine = _joined(coarse, c_more), _joined(fine, f_more)
        relaxed = _relaxed(coarse, fine)
    a, b = (_measures(x, summary.period, continuum) for x in (coarse, fine))
    order = method(s.method).order  # Richardson's p
    amp, per = (_richardson(a[i], b[i], order) for i in (0, 1))
    value = max((abs(v) for v in (amp, per) if math.isfinite(v)), default=math.nan)
    span = float(coarse.window_t[-1])
    reason = (f"Richardson, dt against dt/2 over the run's end + [{span / 2:.4g}, {span:.4g}]"
              + ("" if relaxed else "; the dt/2 shadow still relaxing: a lower bound")
              + ("; a continuum's amplitude and return" if continuum else ""))
    return DtError(value, amp, per, (a[2], b[2]), span, relaxed, reason, time.process_time() - t0)


def shadow_span(summary: Summary, s: SolverSettings) -> float:
    """The shadow's first span: see SPAN_RETURNS."""
    period = summary.period
    if not math.isfinite(period):  # a continuum: its dominant frequency's period
        period = 1.0 / summary.frequency if summary.frequency > 0 else math.nan
    span = 2.0 * SPAN_RETURNS * period if math.isfinite(period) and period > 0 else math.inf
    return max(MIN_SPAN, min(span, s.window))


def start_of(tr: Trajectory) -> CarriedState | None:
    """The run's final state: the kernel's hand-over, or (batched runs keep none) the
    window's last sample with m_x over the last delay from its samples, by the cubic
    Hermite interpolant with slope m_y (eq. 6a); None when the window is shorter than the
    delay."""
    if tr.final is not None:
        return tr.final
    g, t, w = tr.grid, tr.window_t, tr.window
    if len(t) < 2 or t[-1] - t[0] < tr.params.tau:
        return None
    t_m = t[-1] - tr.params.tau + g.dt * np.arange(g.n_delay)
    return CarriedState(tr.params.tau, g.dt, w[:, -1].copy(), hermite(t, w[0], w[1], t_m))


def hermite(t: np.ndarray, x: np.ndarray, y: np.ndarray, at: np.ndarray) -> np.ndarray:
    """x at times ``at`` (within t) from samples x(t) and slopes y(t): cubic Hermite."""
    i = np.clip(np.searchsorted(t, at, side="right") - 1, 0, len(t) - 2)
    h = t[i + 1] - t[i]
    s = (at - t[i]) / h
    h00, h10, h01, h11 = (2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s, -2 * s**3 + 3 * s**2,
                          s**3 - s**2)
    return h00 * x[i] + h10 * h * y[i] + h01 * x[i + 1] + h11 * h * y[i + 1]


def finer(c: CarriedState) -> CarriedState:
    """The same state on a grid of half the step: m_x at the half steps too (cubic
    Lagrange midpoints, core.history.half_steps)."""
    m_x = half_steps(np.append(c.m_x, c.now[0]))[:-1] if c.m_x.size else c.m_x
    return CarriedState(c.tau, c.dt / 2, c.now.copy(), m_x)


def shadow(p: Params, method: str, dt: float, start: CarriedState, span: float) -> Trajectory:
    """``method`` at step dt from ``start`` over ``span``, every sample kept (no λmax)."""
    s = SolverSettings(method=method, dt=dt, t_end=span, window=span, lyap=False,
                       trace_points=2, history=start.name)
    return simulate(p, s, start)


def _joined(a: Trajectory, b: Trajectory) -> Trajectory:
    """Shadow a, continued by b (which starts at a's end): one window, b's final state."""
    t = np.concatenate((a.window_t, a.window_t[-1] + b.window_t[1:]))
    return replace(b, window_t=t, window=np.concatenate((a.window, b.window[:, 1:]), axis=1))


def _late(tr: Trajectory, part: float = 0.5) -> tuple[np.ndarray, np.ndarray]:
    """The samples of the last ``part`` of the shadow."""
    i = int(len(tr.window_t) * (1 - part))
    return tr.window_t[i:], tr.window[:, i:]


def _amplitude(t: np.ndarray, y: np.ndarray) -> float:
    """Refined maxima minus refined minima of m_y (the samples' extremes where none is
    refined: a monotone stretch)."""
    _, top = find_peaks(t, y)
    _, low = find_peaks(t, -y)
    hi = max(float(y.max()), float(top.max()) if top.size else -math.inf)
    lo = min(float(y.min()), -float(low.max()) if low.size else math.inf)
    return hi - lo


def _relaxed(coarse: Trajectory, fine: Trajectory) -> bool:
    """Whether the dt / 2 shadow has stopped moving (RELAXED): its amplitude and the mean
    spacing of its major maxima, between the last two quarters of the span, against the
    differences they measure. The spacing relaxes more slowly than the amplitude: at
    k = 12, tau = 20 (Euler) the dt / 2 shadow's amplitude had settled within 400 time
    units, its return time swung by 0.1 about its limit (20.469) for 1000."""
    t, w = _late(fine)
    h = len(t) // 2
    t_dt, w_dt = _late(coarse)
    for measure in (_amplitude, _spacing):
        q3, q4, q_dt = measure(t[:h], w[1, :h]), measure(t[h:], w[1, h:]), measure(t_dt, w_dt[1])
        if not abs(q4 - q3) <= max(RELAXED * abs(q_dt - q4), RELAXED_FLOOR * abs(q4)):
            return math.isnan(q4 - q3)  # no spacing (rest, one maximum): nothing to wait for
    return True


def _spacing(t: np.ndarray, y: np.ndarray) -> float:
    """The mean spacing of the major maxima of m_y (NaN with fewer than two)."""
    at, top = find_peaks(t, y)
    at = at[top > float(y.min()) + 0.5 * float(np.ptp(y))]
    return float(at[-1] - at[0]) / (len(at) - 1) if len(at) > 1 else math.nan


def _measures(tr: Trajectory, period: float, continuum: bool) -> tuple[float, float, str]:
    """Amplitude, period and label over the last half of a shadow (``period``: the run's,
    a guide to the returns; ``continuum``: the run has no return, so neither has the
    shadow's label a count of maxima).

    Only major maxima count, those above the middle of the range of m_y: at k = 12,
    tau = 20 Euler's stick phase grows a shallow local maximum at m_y = -0.75 in some
    cycles and not in others, which a count of every maximum took for a change of the
    period by 9 %. The period: the time over the most whole returns the half holds (a
    return: as many major maxima as the run's period spans), divided by their number.
    A period of each kind of maximum that differs from another's by more than DRIFT: no
    period (NaN). The label: "rest", or the number of distinct heights of the major maxima (apart by
    more than LABEL_GAP of the amplitude; "continuum" for a run without a return); the
    classifier itself needs more cycles than a short half holds (at k = tau = 10 a half of
    100 was "mixed, 6 switches") and calls a shadow still relaxing by 1e-5 "complex"."""
    t, w = _late(tr)
    y = w[1]
    if len(t) < 3:
        return math.nan, math.nan, "too short"
    amplitude = _amplitude(t, y)
    if not amplitude >= AMPLITUDE_FLOOR * max(1.0, abs(float(np.mean(y)))):
        return amplitude, math.nan, "rest"
    at, top = find_peaks(t, y)
    major = top > float(y.min()) + 0.5 * amplitude
    at, top = at[major], top[major]
    label = "continuum" if continuum else _distinct_words(_distinct(top, amplitude))
    if len(at) < 2 or not math.isfinite(period):
        return amplitude, math.nan, label
    per_return = max(1, round(period * (len(at) - 1) / float(at[-1] - at[0])))  # mean spacing
    returns = (len(at) - per_return) // per_return
    if returns <= 0:
        return amplitude, math.nan, label
    # each kind of maximum (its place in the return) gives a period; they differ while the
    # spacings of a multi-slip orbit drift (a slow transient)
    kinds = [float(at[-1 - j] - at[-1 - j - returns * per_return]) / returns
             for j in range(per_return)]
    spread = (max(kinds) - min(kinds)) / period
    return amplitude, float(np.mean(kinds)) if spread <= DRIFT else math.nan, label


def _distinct(heights: np.ndarray, amplitude: float) -> int:
    """How many heights differ by more than LABEL_GAP of the amplitude (sorted, gaps)."""
    if heights.size == 0:
        return 0
    return 1 + int(np.count_nonzero(np.diff(np.sort(heights)) > LABEL_GAP * amplitude))


def _distinct_words(n: int) -> str:
    """"1 distinct maximum", "2 distinct maxima": a shadow's label."""
    return maxima_words(n).replace(" max", " distinct max")


def _richardson(q_dt: float, q_half: float, order: int) -> float:
    """The relative error of q_dt by Richardson's extrapolation with q_half (signed)."""
    e = (q_dt - q_half) * 2**order / (2**order - 1)
    ref = q_dt - e
    return e / abs(ref) if math.isfinite(e) and ref != 0 else math.nan
