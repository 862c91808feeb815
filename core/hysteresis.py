"""Hysteresis (warm-start) sweeps: follow an attractor along one parameter, up then down.

Each point starts from the final state of the one before: the five variables and m_x,
m_y over the last delay (N + 1 columns of core.period_map's RK4 trajectory, the state of
the discretised equation), handed over exactly. The first point of the up branch starts
from eq. 19 (constant history m_x = delta, as core.orbit_seed.simulate); the down branch
starts from the up branch's last state. Each point is integrated for ``t_settle`` and its
last ``window`` classified by core.classify, as a run's window is.

A state at rest is followed too, and its stability measured along the simulation: the
tangent of the same RK4 map is integrated beside it, its translation mode (a shift of m_x
and its history, neutral) projected out every RENORM_SPAN, and the growth rate of its
m_y envelope (peak to peak per RENORM_SPAN, a line fitted to the logs over the second
half of the point, as core.classify fits a window) is the rest state's leading exponent.
(The growth of the tangent's norm is no use here: the leading mode rotates at the Hopf
frequency, and its norm swings by a factor that, over 3000 units, blurs the rate by
~3e-4, 30 times the rates near the Hopf point.) Where it turns positive
the rest state the branch followed has lost its stability, and no simulation from that
exact state would ever leave it (round-off grows at 4.5e-5 per unit time at k = 6.2,
tau = 10): the point is integrated again from the state kicked by KICK in m_y, span after span of
t_settle until it lands on another attractor, and the branch goes on from there
("jumped"). Nothing else perturbs the handover.

Where a branch changes regime: the grid gives a bracket, the last value of the branch
still on its first point's kind of state (a stable rest, or the first point's regime) and
the first value past it (``Transition.before`` and ``.after``). The transition is then
refined inside that bracket by bisection (``refine``), each middle value settled for
t_settle from the state carried from the last value found on the old attractor, as the
sweep itself carries it (the bracket's old end first, then each middle found old), until
half the bracket is at most ``tol`` times the value (TOL, relative). ``onset_up`` and
``offset_down`` are the refined values. What "still on the old attractor" means:

* Up from rest, the onset is where the rest state stops being the attractor reached: the
  Hopf point. A middle value whose window has left rest is past it. One still at rest is
  decided by linear theory, the sign of the leading root of the rest state it sits at
  (core.rest_stability.rest_exponent, with the noise d): within ~0.1 % of k_H at tau = 10
  the rates are ~1e-6 per unit time, below what the growth measured along the simulation
  resolves (~4e-6, tests/unit/test_hysteresis.py), and a rest state that is unstable there
  would take ~1e5 units to leave. Only where the root cannot be computed does the measured
  growth decide.
* Down from the cycle, the offset is where the cycle is lost: the fold of cycles. A middle
  value whose window still shows the first point's regime is on the cycle; any other
  outcome (rest, another regime, a run leaving the finite range) is past it. Near the fold
  the cycle's ghost slows the fall, but within the tolerance it is short: at tau = 10,
  k = 1.2127 (0.1 % below the fold 1.2139) the run from the cycle at 1.3 is at rest well
  inside the default 6000 units.

Between onset and offset lies, by simulation alone, the band where the outcome depends on
the initial state; continuation (core.continuation) finds its ends as the Hopf point and
the fold of cycles independently (tests/unit/test_hysteresis_brackets.py compares them).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from core.classify import Summary, classify
from core.model import coefficients
from core.orbit import Grid, OrbitError
from core.params import Params
from core.period_map import flow
from core.rest_stability import NEUTRAL_TOL, rest_exponent

#: The kick in m_y (model units) that lets a branch leave a rest state found unstable,
#: and the spans of t_settle it may take to land (settled, and not still growing away
#: from rest): from 1e-3 at k = 6.2, tau = 10 (growth 4.6e-5 per unit time) the cycle is
#: reached after ~1.5e5 units, 25 spans of the default 6000.
KICK = 1e-3
JUMP_SPANS = 60
#: The tangent is renormalised (translation projected out) every this many time units.
RENORM_SPAN = 50.0
#: Default time integrated at each point, and the analysis window at its end. At tau = 10
#: a rest state next to the Hopf point decays or grows at ~1e-5 per unit time (k = 6.16):
#: its exponent needs the tangent's other modes (decaying at >= 1e-2) gone, ~1000 units,
#: and its sign then holds over 5000 more (tests/unit/test_hysteresis.py).
T_SETTLE, WINDOW = 6000.0, 1000.0
#: Default tolerance of a refined transition, relative to its value: the bisection stops
#: when half its bracket is at most this times the middle. Its cost, measured at tau = 10, k
#: from 0.5 to 8 in 40 points (the sweep itself: 7.0 s CPU for its 80 points): the onset
#: 4 extra settle runs and 6.2 s (most of it the rest state's root with noise,
#: core.rest_stability, ~1.4 s each), the offset 7 settle runs and 0.3 s; at 1e-4, 8 runs
#: and 11.7 s, 10 runs and 0.5 s. The results: 6.1430 and 1.21439 (Hopf point 6.1462 with
#: the noise, fold 1.2139).
TOL = 1e-3
#: Bisection steps at most (a transition at a value 0 meets no relative tolerance).
MAX_BISECTIONS = 60


@dataclass(frozen=True)
class WarmPoint:
    """One point of a branch: the parameter's value, the regime and detail of its window,
    the amplitude (peak-to-peak m_y) there, the growth rate of perturbations of the state
    at rest it ends at, or of the rest state it was kicked off (``jumped``); NaN when it
    neither ends at rest nor jumped."""

    value: float
    regime: str
    detail: str
    amplitude: float
    growth: float
    jumped: bool = False

    @property
    def stable_rest(self) -> bool:
        return self.regime == "sliding" and not self.jumped and not self.growth > 0.0


@dataclass(frozen=True)
class Transition:
    """Where a branch leaves its attractor: the grid's bracket, ``before`` (the last value
    on the old attractor) and ``after`` (the first on the new), and ``value``, the middle
    of the bracket bisection left (within ``tol`` of the transition, relative); ``settles``
    counts the bisection's settle runs, ``by_theory`` those at rest that linear theory
    decided (the module docstring says why)."""

    before: float
    after: float
    value: float
    tol: float
    settles: int = 0
    by_theory: int = 0


@dataclass(frozen=True)
class Hysteresis:
    """Both branches and where each leaves its attractor: ``onset_up`` and ``offset_down``
    the refined values (None: the branch keeps its attractor), ``onset`` and ``offset``
    with their brackets."""

    param: str
    up: list[WarmPoint]
    down: list[WarmPoint]
    onset: Transition | None = None
    offset: Transition | None = None

    @property
    def onset_up(self) -> float | None:
        return None if self.onset is None else self.onset.value

    @property
    def offset_down(self) -> float | None:
        return None if self.offset is None else self.offset.value


def initial_state(p: Params, g: Grid) -> np.ndarray:
    """Eq. 19 as N + 1 columns: m_x = delta before t = 0 (m_y there is its slope, 0), every
    variable delta at t = 0."""
    state = np.zeros((5, g.n_delay + 1))
    state[0, :] = p.delta
    state[:, g.n_delay] = p.delta
    return state


def _tangent_start(g: Grid) -> np.ndarray:
    """A fixed, generic start for the tangent (reproducible), norm 1."""
    e = np.random.default_rng(19).standard_normal((5, g.n_delay + 1))
    return e / math.sqrt(float(np.sum(e * e)))


def _reduce(e: np.ndarray, g: Grid) -> float:
    """Project the translation out of the tangent columns (subtract the current e_x from
    every m_x entry), scale them to norm 1 (history weighted by dt), return the log of
    the norm they had."""
    e[0, :] -= e[0, -1]
    norm = math.sqrt(float(np.sum(e[:, -1] ** 2) + g.dt * np.sum(e[:2, :-1] ** 2)))
    e /= norm
    return math.log(norm)


def settle(p: Params, g: Grid, state: np.ndarray, t_settle: float, window: float
           ) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """Integrate from ``state`` for t_settle: the final state (N + 1 columns), the window's
    times and samples (rows m_x, m_y, ...; every step), and the growth rate of the
    tangent over the second half. Raises OrbitError when the run leaves the finite range."""
    coef = coefficients(p)
    n = g.n_delay
    chunk = max(1, round(RENORM_SPAN / g.dt))
    n_steps = max(chunk, math.ceil(t_settle / g.dt / chunk) * chunk)
    first = n_steps - min(n_steps, max(1, round(window / g.dt)))  # the window's first step
    traj = np.empty((5, n + chunk + 1))
    e_traj = np.empty((5, n + chunk + 1))
    traj[:, :n + 1] = state
    e_traj[:, :n + 1] = _tangent_start(g)
    scale = 0.0  # log of the tangent's size before its renormalisations so far
    envelope: list[float] = []  # log peak-to-peak of the tangent's m_y, chunk by chunk
    kept: list[np.ndarray] = []
    done = 0
    while done < n_steps:
        filled = flow(coef, g.dt, n, traj, e_traj, True)
        if filled < traj.shape[1]:
            raise OrbitError(f"the run left the finite range at t = "
                             f"{(done + filled - n - 1) * g.dt:.4g}")
        steps = np.arange(done + 1, done + chunk + 1)  # the steps this chunk added
        if steps[-1] >= first:
            kept.append(traj[:, n + 1:][:, steps >= first].copy())
        traj[:, :n + 1] = traj[:, chunk:]
        e_traj[:, :n + 1] = e_traj[:, chunk:]
        envelope.append(math.log(float(np.ptp(e_traj[1, n + 1:])) or 1e-300) + scale)
        scale += _reduce(e_traj[:, :n + 1], g)
        done += chunk
    half = np.array(envelope[len(envelope) // 2:])
    centres = (np.arange(len(envelope) - half.size, len(envelope)) + 0.5) * chunk * g.dt
    growth = float(np.polyfit(centres, half, 1)[0]) if half.size > 1 else math.nan
    win = np.concatenate(kept, axis=1)
    t = (n_steps - win.shape[1] + 1 + np.arange(win.shape[1])) * g.dt
    return traj[:, :n + 1].copy(), t, win, growth


def point(p: Params, g: Grid, state: np.ndarray, name: str, t_settle: float, window: float
          ) -> tuple[WarmPoint, np.ndarray]:
    """One point of a branch from ``state``: kicked off a rest state found unstable (see
    the module docstring). Returns the point and the state it hands over."""
    value = float(getattr(p, name))
    final, t, win, growth = settle(p, g, state, t_settle, window)
    summary = classify(t, win, p=p, follow_branch=False)
    jumped = False
    trigger = growth
    if _leaving_rest(summary, growth):
        final = final.copy()
        final[1, -1] += KICK
        jumped = True
        for _ in range(JUMP_SPANS):  # until it lands: settled, and not still leaving rest
            final, t, win, growth = settle(p, g, final, t_settle, window)
            summary = classify(t, win, p=p, follow_branch=False)
            if summary.settled and not _leaving_rest(summary, growth):
                break
    rest = summary.regime == "sliding" or summary.attractor == "unstable-fixed-point"
    return WarmPoint(value, summary.regime, summary.detail, summary.amplitude,
                     trigger if jumped else growth if rest else math.nan, jumped), final


def _leaving_rest(summary: Summary, growth: float) -> bool:
    """Whether the point rests at a state that is unstable: by the growth measured along
    the simulation, or by linear theory (core.classify's ``unstable-fixed-point``: the
    window has not departed, whatever regime it is headed for)."""
    return (summary.regime == "sliding" and growth > 0.0) or summary.attractor == "unstable-fixed-point"


def branch(base: Params, name: str, values: Sequence[float], g: Grid, state: np.ndarray,
           t_settle: float, window: float,
           progress: Callable[[WarmPoint], None] | None = None
           ) -> tuple[list[WarmPoint], list[np.ndarray], str]:
    """Warm-started points along ``values`` from ``state``: the points, the state each
    handed over (none for a last point that left the finite range), and why the branch
    ended early ("" if it did not: a run that leaves the finite range ends it, since there
    is no state to hand over)."""
    points: list[WarmPoint] = []
    states: list[np.ndarray] = []
    for value in values:
        try:
            pt, state = point(base.with_(**{name: value}), g, state, name, t_settle, window)
        except OrbitError as exc:
            points.append(WarmPoint(value, "unstable", str(exc), math.nan, math.nan))
            return points, states, f"{name} = {value:g}: {exc}"
        points.append(pt)
        states.append(state)
        if progress is not None:
            progress(pt)
    return points, states, ""


def _same_kind(first: WarmPoint, pt: WarmPoint) -> bool:
    """Whether ``pt`` is on the first point's kind of state: a stable rest, or (starting
    away from rest) the first point's regime."""
    return pt.stable_rest if first.stable_rest else pt.regime == first.regime


def past(points: Sequence[WarmPoint]) -> int | None:
    """The index of the first point that left the first point's kind of state (None: the
    branch keeps it); the point before it is the last on the old attractor."""
    for i, pt in enumerate(points[1:], 1):
        if not _same_kind(points[0], pt):
            return i
    return None


def _still_old(first: WarmPoint, p: Params, g: Grid, state: np.ndarray, t_settle: float,
               window: float) -> tuple[bool, np.ndarray, bool]:
    """Settle at p from ``state``: whether it is still on the first point's kind of state
    (the module docstring says how each direction is decided), the final state, and
    whether linear theory decided."""
    try:
        final, t, win, growth = settle(p, g, state, t_settle, window)
    except OrbitError:
        return False, state, False  # it left the finite range: not on the old attractor
    summary = classify(t, win, p=p, follow_branch=False)
    if not first.stable_rest:
        return summary.regime == first.regime, final, False
    if summary.regime != "sliding" and summary.attractor != "unstable-fixed-point":
        return False, final, False  # it left rest
    try:
        root = rest_exponent(p)
    except ArithmeticError:  # no root: the growth measured along the simulation decides
        return not growth > 0.0, final, False
    return root < NEUTRAL_TOL, final, True


def refine(base: Params, name: str, points: Sequence[WarmPoint], states: Sequence[np.ndarray],
           g: Grid, t_settle: float, window: float, tol: float = TOL) -> Transition | None:
    """The branch's transition (``past``) refined by bisection inside its grid bracket, from
    the state the last point on the old attractor handed over (``states[i]``: what point i
    handed over); None when the branch keeps its attractor."""
    i = past(points)
    if i is None:
        return None
    first = points[0]
    old, new = points[i - 1].value, points[i].value
    state = states[i - 1]
    settles = by_theory = 0
    for _ in range(MAX_BISECTIONS):
        middle = 0.5 * (old + new)
        if abs(new - old) <= 2.0 * tol * abs(middle):
            break
        still, final, theory = _still_old(first, base.with_(**{name: middle}), g, state,
                                          t_settle, window)
        settles += 1
        by_theory += theory
        if still:
            old, state = middle, final  # carried on, as the sweep carries it
        else:
            new = middle
    return Transition(points[i - 1].value, points[i].value, 0.5 * (old + new), tol, settles,
                      by_theory)


def hysteresis(base: Params, name: str, start: float, stop: float, n_points: int,
               dt: float = 0.01, t_settle: float = T_SETTLE, window: float = WINDOW,
               progress: Callable[[str, WarmPoint], None] | None = None,
               tol: float = TOL) -> Hysteresis:
    """Up from ``start`` to ``stop`` in n_points equal steps, then back down, each point
    warm-started from the previous one's final state, and each branch's transition refined
    to ``tol`` (relative; the module docstring says how)."""
    if name == "tau":
        raise OrbitError("a hysteresis sweep cannot follow tau: the state's history is one "
                         "delay long, so it changes size along the sweep")
    values = np.linspace(start, stop, n_points)
    g = Grid.of(base, dt)
    first = base.with_(**{name: float(values[0])})
    up, up_states, end = branch(base, name, values, g, initial_state(first, g), t_settle,
                                window, None if progress is None else lambda pt: progress("up", pt))
    down: list[WarmPoint] = []
    down_states: list[np.ndarray] = []
    if not end:
        down, down_states, _ = branch(base, name, values[::-1], g, up_states[-1], t_settle,
                                      window, None if progress is None
                                      else lambda pt: progress("down", pt))
    return Hysteresis(name, up, down,
                      refine(base, name, up, up_states, g, t_settle, window, tol),
                      refine(base, name, down, down_states, g, t_settle, window, tol))


__all__ = ["Hysteresis", "Transition", "WarmPoint", "hysteresis", "initial_state",
           "past", "refine", "settle"]
