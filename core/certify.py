"""Certify a run's attractor from the run's own final state, after its window is classified.

The window's label (core.classify) says what the last 1000 time units show. A certificate
says which attractor the run has reached, by a second, independent argument:

* **Fixed point.** Linear theory (the rest state's leading nonzero root, core.rest_stability;
  the always-zero root of the m_x shift left out) is negative, and the window agrees: its
  envelope decays at a rate consistent with that root, or is already at round-off.
* **Periodic orbit.** Newton-Krylov shooting (core.shooting) converges from the state at
  the end of the window (the run's final state: m_x and m_y over the last delay, which the
  window holds in full, in a batch's lane too), seeded with the window's return time. The
  orbit is RK4's at ORBIT_DT (core.periodic_orbit), coarser than the paper's Euler run: the
  certificate says so. Its minimal period is confirmed (a shot over a fraction of the
  period that also closes makes that fraction the period), and its Floquet multipliers
  (core.floquet), the flow's and the translation's (both 1) apart, lie inside the unit
  circle by STABLE_MARGIN (or by the flow multiplier's distance from 1, if larger). Where
  that step may be what failed (sharp slips: Newton leaves the orbit, finds one other than
  the window's, or leaves its minimal period undecided), all of it is tried once more at
  dt / REFINE, and the certificate says so.

Anything else is not certified, the certificate saying why. The Newton iteration has a
budget (NEWTON_BUDGET steps, KRYLOV_BUDGET products a step): a run that needs more is "not
certified: budget", so that certification costs a bounded share of a run (docs/speed.md).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np

from core.classify import Summary, find_peaks, maxima_words
from core.params import Params
from core.rest_stability import NEUTRAL_TOL, rest_exponent
from core.returns import distinct_maxima
from core.solve import Trajectory
from core.stability import hopf_period, leading_exponent

if TYPE_CHECKING:  # the orbit kernels load only when an orbit is certified
    from core.orbit import Grid, PeriodMap
    from core.shooting import Solution

#: The step of the shooting (RK4): core.periodic_orbit's ORBIT_DT (its period is accurate
#: to ~1e-9 relative against finer dt) ...
CERTIFY_DT = 0.01
#: ... or coarser, so that a delay holds at most this many steps: the shooting's unknowns
#: (2 N + 4) and a product's steps (a period, ~tau to 2 tau) grow with tau / dt, and at
#: tau = 60, dt 0.01 certification cost 40 % of the paper's run (benchmarks/bench_certify.py).
#: At tau = 60 the step is 0.03 (0.25 s instead of 1.1 s at k = 7): its period, 60.617270,
#: differs from dt 0.01's by 2e-8 and from an independent RK4 at dt 0.005 by 1.2e-7
#: (tests/integration/test_minimal_period.py).
MAX_DELAY_STEPS = 2000
#: Newton steps allowed from the run's final state. Measured from Euler's state (dt 1e-3,
#: t_end 2e4) on RK4's map (dt 0.01): 2 steps at k = tau = 10 and at b = 15, k = 12,
#: tau = 6, 3 at b = 17-18 and at k = 7, tau = 60; core.orbit allows 25 from a seed 1e-2
#: off. A run that needs more is "not certified within the budget" (k = 20, tau = 10, a
#: long transient: residual 2e-3 after 8 steps). With 8 steps of 120 products that
#: failure cost 9.5 % of the paper's run (benchmarks/bench_certify.py), the most of any
#: point measured: 5 steps of 80 leave the converging runs their margin.
NEWTON_BUDGET = 5
#: Krylov products per Newton step (GMRES's restart length): measured 15 a step at
#: k = tau = 10, 34 at k = 7, tau = 60.
KRYLOV_BUDGET = 80
#: Multipliers computed (the leading ones by modulus; ARPACK's Arnoldi with
#: ARNOLDI_VECTORS vectors).
N_MULTIPLIERS = 6
ARNOLDI_VECTORS = 40
#: ARPACK's restarts allowed (each costs about ARNOLDI_VECTORS - N_MULTIPLIERS products):
#: k = tau = 10 needs 1 (41 products); where the multipliers crowd near the unit circle
#: (large tau near the Hopf point) it would need hundreds: "not certified: budget".
ARNOLDI_RESTARTS = 10
#: A nontrivial multiplier must lie inside the unit circle by this much for the orbit to
#: count as stable: ten times core.floquet.UNIT_TOL, the distance within which a multiplier
#: is on the circle (the flow multiplier's own distance from 1, RK4's error over a period,
#: is ~1e-9 at dt = 0.01, and ARPACK's relative accuracy is 1e-10). An orbit closer to the
#: circle than this is marginal: a fold, a period doubling or a torus nearby.
STABLE_MARGIN = 1e-5
#: The orbit Newton finds is the window's when their amplitudes and periods agree to this
#: (relative): the dt-sensitive threshold of core.accuracy. Either side may be the one
#: off: Euler at tau = 0.5, k = 37.6 (amplitude 0.790 against the orbit's 0.496, which RK4
#: at dt 1e-4 confirms), or RK4 at CERTIFY_DT itself where the slips are sharp (b = 24,
#: k = 12, tau = 7.43: RK4 at 0.01 gives 10.237, at 1e-3 9.771, Euler at 1e-3 and 5e-4
#: 9.773 and 9.772). The regenerated report found 1700 of its 5381 runs so (before the
#: retry at dt / REFINE, which certifies the second kind): the certificate then says so,
#: and blames the run's scheme only when both steps find the same orbit.
MATCH_TOL = 0.01
#: A shot over T / j closes (the period is T / j, not T) when its residual is below this
#: fraction of the orbit's amplitude: Newton's tolerance is 1e-10, an orbit of period T that
#: is not T / j-periodic misses by the difference of its distinct maxima (2e-4 A at the
#: closest we measured: tau = 10, k = 20).
SUBPERIOD_TOL = 1e-6
#: ... but a miss below this fraction may be the certifier's step's, not the orbit's: at
#: b = 22, k = 12, tau = 2 (sharp slips) the window returns after 8 periods of 3.8024 and
#: at dt 0.01 the shots over T / 8, T / 4, T / 2 miss by 1.3e-4, 1.8e-4, 2.7e-5 of the
#: amplitude; at dt 0.005 by 7.0e-6, 7.5e-6, 4.8e-6, at 0.0025 by 8.8e-7, 6.9e-7, 3.8e-7, at
#: 0.00125 by 1.3e-8, 9e-9, 3.1e-8 (RK4's cubic end interpolation breaks the orbit's time
#: symmetry by its error). Such a miss is decided at REFINE times finer (_minimal), where a
#: scheme's miss falls more than SHRINK times and below CLOSED_FINE (the measured fall: 71 to
#: 260 times, over dt / 4), and an orbit's own difference does not fall (by less than FELL).
AMBIGUOUS = 1e-2
SHRINK, CLOSED_FINE, FELL = 32.0, 1e-5, 4.0
#: Where the certifier's step may be what failed (Newton left the orbit, the orbit is not
#: the window's, its period is undecided, or the flow multiplier's error leaves its
#: stability undecided), the certificate is tried again once at dt / REFINE. Measured:
#: b = 24, k = 12, tau = 7.43 (sharp slips), the orbit at dt 0.01 has amplitude 10.202
#: and 13 maxima, at 0.005 and 0.0025 9.77107 and 1 maximum (period 9.2035415, 9.2035377).
REFINE = 4
#: The window's decay rate agrees with the leading root within this fraction of the root
#: (Euler's map carries a bias: -0.00393 against the root -0.003944 at tau = 10, k = 4,
#: 0.4 %; 0.36 % at tau = 0.2, k = 12), or within DECAY_RATE_ABS where the decay is too slow
#: to measure in the window (1e-5: a 1 % change over a window of 1000).
DECAY_RATE_REL = 0.1
DECAY_RATE_ABS = 1e-5
#: The window's envelope is at round-off when its amplitude is below this, relative to
#: max(1, |m_y|): a rest state reached long before the window leaves 0 to 1.5e-10
#: (core.classify.AMPLITUDE_FLOOR's measurement).
ROUND_OFF = 1e-9


@dataclass(frozen=True, slots=True)
class Certificate:
    """Whether a run's attractor is certified, and how (``text``, or why not); for an
    orbit its period, amplitude (peak-to-peak m_y), maxima of m_y in one period (slips,
    and their heights) and nontrivial Floquet multipliers, largest modulus first."""

    certified: bool
    text: str
    period: float = math.nan
    amplitude: float = math.nan
    slips: int = 0
    maxima: tuple[float, ...] = ()
    multipliers: tuple[complex, ...] = ()
    #: A certified fixed point's leading root (1/time; NaN otherwise): its lambda_max in
    #: the continuous model (core.certified_stop.certified_lambda).
    root: float = math.nan
    #: The run's own scheme at its dt is measurably off the model here (a window that
    #: grows where theory decays, or an orbit other than the model's): core.point then
    #: flags the run dt-sensitive, whatever the shadow estimate said.
    scheme_off: bool = False

    @property
    def pairs(self) -> list[list[float]]:
        """The certified orbit's multipliers as [re, im] pairs (the result field
        ``multipliers``; empty when nothing was certified: an unstable orbit's are in the
        text)."""
        if not self.certified:
            return []
        return [[float(m.real), float(m.imag)] for m in self.multipliers]

    @property
    def certified_slips(self) -> int:
        """Slips a period of the certified orbit (the result field ``slips``); 0 when
        nothing was certified or at rest."""
        return self.slips if self.certified else 0


NOT_ATTEMPTED = Certificate(False, "not attempted")


def certify(tr: Trajectory, s: Summary, retry: bool = True) -> Certificate:
    """The certificate of a run whose window is classified as ``s``; ``retry`` = False:
    an orbit's first attempt alone, without the retry at dt / REFINE (what the retry
    costs and gains is measured against it: benchmarks/bench_certify.py)."""
    if tr.blew_up:
        return Certificate(False, f"blew up at t = {tr.t_blowup:.6g}")
    if s.attractor == "fixed-point":
        return _fixed_point(tr, s)
    if s.attractor == "unstable-fixed-point":
        return _unstable_rest(tr.params)
    if s.attractor == "periodic" and s.period_count > 0:
        if not math.isfinite(s.period):
            return Certificate(False, "too few maxima in the window to seed the period")
        return _periodic(tr, s, retry)
    if s.attractor in ("fast-branch", "variance-state"):
        return Certificate(False, f"rest on a steady state off the fixed point ({s.attractor}): "
                                  "no linear theory of it here")
    return Certificate(False, f"no return in the window ({s.attractor or s.regime}): "
                              "no periodic orbit to shoot for")


def _fixed_point(tr: Trajectory, s: Summary) -> Certificate:
    """Linear theory and the window's decay agree (the module docstring)."""
    p = tr.params
    try:
        root = rest_exponent(p)
        if root == -math.inf:  # below the stability gate: stable without a computation, and
            root = leading_exponent(p)  # the noise-free root is the rate (noise shifts it ~d)
    except ArithmeticError as exc:  # k ~ 1e-283: every root of the delay factor is ~0
        return Certificate(False, f"linear theory undecided: {exc}")
    if root >= -NEUTRAL_TOL:
        return Certificate(False, f"leading root {root:+.2e}/t is not < 0")
    y = tr.window[1]
    level = max(1.0, abs(float(np.mean(y))))
    if float(np.ptp(y)) <= ROUND_OFF * level:
        return Certificate(True, f"fixed point: leading root {root:+.3e}/t < 0, window at "
                                 f"round-off (m_y peak-to-peak {float(np.ptp(y)):.1e})", root=root)
    rate = _decay_rate(tr.window_t, y, level)
    if not math.isfinite(rate):
        return Certificate(False, f"leading root {root:+.3e}/t < 0, but the window's decay "
                                  "could not be measured")
    if rate >= 0.0:  # Euler's O(dt) anti-damping next to a Hopf point: its rest is unstable
        return Certificate(False, f"leading root {root:+.3e}/t < 0, but the window grows at "
                                  f"{rate:+.3e}/t: the run's scheme at its dt does not rest "
                                  "where the model does", scheme_off=True)
    if abs(rate - root) <= max(DECAY_RATE_REL * abs(root), DECAY_RATE_ABS):
        return Certificate(True, f"fixed point: leading root {root:+.3e}/t < 0, window decays "
                                 f"at {rate:+.3e}/t", root=root)
    return Certificate(False, f"the window decays at {rate:+.3e}/t, linear theory says "
                              f"{root:+.3e}/t: not yet the linear decay to the fixed point")


def _unstable_rest(p: Params) -> Certificate:
    """A window still at a rest state that linear theory calls unstable (core.classify)."""
    try:
        root = f"{rest_exponent(p):+.2e}/t"
    except ArithmeticError:
        root = "positive"
    return Certificate(False, f"leading root {root} > 0: the window has not departed from the "
                              "unstable rest state, its attractor is not reached")


def _decay_rate(t: np.ndarray, y: np.ndarray, level: float) -> float:
    """The envelope's growth rate over the window: a line through the log of the
    peak-to-peak of m_y in 10 sub-windows, those above round-off."""
    parts = np.array_split(np.arange(len(y)), 10)
    centres = np.array([t[i].mean() for i in parts])
    amps = np.array([np.ptp(y[i]) for i in parts])
    keep = amps > ROUND_OFF * level
    if np.count_nonzero(keep) < 3:
        return math.nan
    return float(np.polyfit(centres[keep], np.log(amps[keep]), 1)[0])


def _periodic(tr: Trajectory, s: Summary, retry: bool = True) -> Certificate:
    """Newton-Krylov shooting from the end of the window, seeded with its return time, at
    the certifier's step; once more at REFINE times finer where that step may be what
    failed (_Attempt.retry)."""
    from core.orbit import Grid, OrbitError

    p = tr.params
    try:
        g = Grid.of(p, max(CERTIFY_DT, p.tau / MAX_DELAY_STEPS))
    except OrbitError as exc:  # tau = 0
        return Certificate(False, str(exc))
    t = tr.window_t
    if len(t) < 2 or t[-1] - t[0] < p.tau + 2 * g.dt:
        return Certificate(False, f"the window ({t[-1] - t[0] if len(t) else 0:g}) is shorter "
                                  f"than the delay: no final state to shoot from")
    first = _attempt(tr, s, g)
    if not (retry and first.retry):
        return first.certificate
    fine = Grid.of(p, g.dt / REFINE)
    return _attempt(tr, s, fine, coarse=first).certificate


@dataclass(frozen=True)
class _Attempt:
    """One certification at one step: its certificate; ``retry``: a finer step may decide
    what this one could not (``why``: what it could not, for the finer one's text);
    ``closures``: the shots over T / j that closed only to between SUBPERIOD_TOL and
    AMBIGUOUS of the amplitude (j -> miss / amplitude); ``dt``: the step."""

    certificate: Certificate
    retry: bool = False
    why: str = ""
    closures: dict[int, float] = field(default_factory=dict)
    dt: float = math.nan
    #: The orbit found, where it is not the window's.
    period: float = math.nan
    amplitude: float = math.nan


def _attempt(tr: Trajectory, s: Summary, g: Grid, coarse: _Attempt | None = None) -> _Attempt:
    """Certification on the grid ``g``; ``coarse``: the attempt at the coarser step it
    follows (its undecided closures are decided here against it, its failure is named)."""
    # imported here: the orbit kernels and scipy's sparse solvers serve only this path
    from core.floquet import multipliers
    from core.orbit import OrbitError, PeriodMap
    from core.shooting import correct

    p = tr.params
    t = tr.window_t
    z0 = state_from_window(t, tr.window, g, float(t[-1]))
    zdot = (z0 - state_from_window(t, tr.window, g, float(t[-1]) - g.dt)) / g.dt
    pm = PeriodMap(p, g)
    where = f"RK4 at dt {g.dt:.4g}"
    if coarse is not None:
        where += f", refined: at dt {coarse.dt:.4g} {coarse.why}"
    try:
        sol = correct(pm, z0, s.period, z0, zdot, max_steps=NEWTON_BUDGET,
                      max_products=KRYLOV_BUDGET)
    except OrbitError as exc:
        budget = "did not converge" in str(exc)
        head = (f"not certified within the budget ({NEWTON_BUDGET} Newton steps of "
                f"{KRYLOV_BUDGET} Krylov products): " if budget else "")
        # a budget spent on a slow transient is not the step's doing; a Newton that left
        # the orbit may be (b = 24, k = 12, tau = 7.43: at dt 0.01 it diverged, at 0.0025
        # it converged in one step)
        return _Attempt(Certificate(False, f"{head}Newton from the final state ({where}): {exc}"),
                        retry=not budget, why=f"Newton failed ({exc})", dt=g.dt)
    sol, closures, undecided = _minimal(pm, sol, coarse)
    m_y = sol.shot.traj[1, g.n_delay:sol.shot.col + 1]
    amplitude = float(np.ptp(m_y))
    if undecided:
        return _Attempt(Certificate(False, f"the orbit's period is not decided ({where}): "
                                           f"{undecided}"), dt=g.dt)
    if closures:
        said = ", ".join(f"T / {j} to {r:.1e}" for j, r in closures.items())
        return _Attempt(Certificate(False, f"the orbit's period is not decided ({where}): "
                                           f"period T = {sol.period:.8g}, shots over {said} "
                                           "of its amplitude"),
                        retry=True, why=f"left its period undecided (shots over {said} of "
                                        "its amplitude)", closures=closures, dt=g.dt)
    apart = _apart(s, sol.period, amplitude)
    if apart:
        same = coarse is not None and not _apart(
            replace(s, period=coarse.period, amplitude=coarse.amplitude), sol.period, amplitude,
            MATCH_TOL / 10)
        blame = ("the run's scheme is off at its step (the certifier's orbit is the same at "
                 "both steps), or it is another orbit" if same else
                 "the run's scheme or the certifier's is off at its step, or it is another orbit")
        return _Attempt(Certificate(False, f"the orbit Newton found from the final state "
                                           f"({where}: period {sol.period:.8g}, amplitude "
                                           f"{amplitude:.6g}) is not the window's ({apart}): "
                                           f"{blame}"),
                        retry=True, why=f"found another orbit (period {sol.period:.8g}, "
                                        f"amplitude {amplitude:.6g})", dt=g.dt,
                        period=sol.period, amplitude=amplitude)
    try:
        mult = multipliers(pm, sol.shot, N_MULTIPLIERS, ARNOLDI_VECTORS, ARNOLDI_RESTARTS)
    except (OrbitError, ValueError) as exc:  # ValueError: ARPACK's sizes at a tiny delay
        return _Attempt(Certificate(False, f"not certified within the budget: an orbit of "
                                           f"period {sol.period:.6g} ({where}), its multipliers "
                                           f"not found ({ARNOLDI_RESTARTS} Arnoldi restarts): "
                                           f"{exc}"), dt=g.dt)
    maxima = orbit_maxima(m_y)
    others = tuple(complex(m) for m in mult.nontrivial)
    top = max((abs(m) for m in others), default=0.0)
    error = abs(mult.flow - 1.0)
    said = (f"period {sol.period:.8g}, amplitude {amplitude:.6g}, {len(maxima)} "
            f"slip{'s' if len(maxima) != 1 else ''} a period, |multipliers| <= {top:.6g} "
            f"({where}; Newton {sol.steps} steps, residual {sol.residual:.1e}"
            + (f"; flow multiplier {error:.1e} from 1" if error > STABLE_MARGIN else "") + ")")
    verdict = orbit_verdict(top, error)
    head = VERDICT_TEXT[verdict].format(margin=max(STABLE_MARGIN, error))
    return _Attempt(Certificate(verdict == "stable", f"{head}: {said}",
                                sol.period, amplitude, len(maxima), maxima, others),
                    retry=verdict == "marginal" and error > STABLE_MARGIN,
                    why=f"left its stability undecided (flow multiplier {error:.1e} from 1)",
                    dt=g.dt)


#: What a certificate says of an orbit by its verdict (orbit_verdict).
VERDICT_TEXT = {
    "stable": "stable orbit",
    "unstable": "the orbit is unstable",
    "marginal": ("the orbit's stability is undetermined: a multiplier within {margin:.1g} of "
                 "the unit circle, nearer than a certificate decides"),
}


def orbit_verdict(top: float, error: float = 0.0) -> str:
    """"stable", "marginal" or "unstable" by ``top``, the largest modulus of the orbit's
    nontrivial multipliers, against STABLE_MARGIN or the multipliers' ``error`` if larger
    (the flow multiplier's distance from 1, which is exactly 1 in the model). Marginal is
    not "unstable": the 3-slip orbit at k = 18, tau = 10 has |mu| = 0.9999913 (DDE-BIFTOOL
    0.99999133) and attracts (a run from eq. 19 approaches it at ln|mu| / T), but so near
    the circle a certificate claims neither."""
    margin = max(STABLE_MARGIN, error)
    if top > 1.0 + margin:
        return "unstable"
    if top >= 1.0 - margin:
        return "marginal"
    return "stable"


def _apart(s: Summary, period: float, amplitude: float, tol: float = MATCH_TOL) -> str:
    """How the orbit Newton found differs from the window's, if by more than ``tol``
    (empty: it is the window's orbit). The window may return after a multiple of the
    orbit's period (a flat maximum's timing noise), so its period is compared with the
    nearest multiple."""
    if not (math.isfinite(s.amplitude) and s.amplitude > 0.0):
        return "the window has no amplitude"
    far = []
    if abs(amplitude / s.amplitude - 1.0) > tol:
        far.append(f"amplitude {s.amplitude:.6g}")
    j = max(1, round(s.period / period)) if math.isfinite(s.period) else 1
    if math.isfinite(s.period) and abs(s.period / (j * period) - 1.0) > tol:
        far.append(f"period {s.period:.8g}")
    return ", ".join(far)


def _minimal(pm: PeriodMap, sol: Solution, coarse: _Attempt | None = None
             ) -> tuple[Solution, dict[int, float], str]:
    """The orbit at its minimal period (the window may return after a multiple of it), the
    shots over T / j this step leaves undecided, and why the period is undetermined (empty
    if it is not). A shot over sol.period / j (j up to the orbit's maxima per period) that
    closes to SUBPERIOD_TOL of the amplitude is corrected at that period; one that misses
    by less than AMBIGUOUS is undecided at the certifier's step (its miss may be the
    scheme's) and decided at the finer one (``coarse``: the attempt that left it): there the
    period is T / j if the miss fell as the scheme's error falls (below SUBPERIOD_TOL, or
    SHRINK times and below CLOSED_FINE), T if it did not fall (by less than FELL), and
    undetermined between."""
    from core.orbit import OrbitError
    from core.shooting import correct
    m_y = sol.shot.traj[1, pm.g.n_delay:sol.shot.col + 1]
    amplitude = float(np.ptp(m_y))
    w = pm.g.weights
    unsure: dict[int, float] = {}
    closures, coarse_dt = (coarse.closures, coarse.dt) if coarse is not None else ({}, math.nan)
    for j in range(len(orbit_maxima(m_y)), 1, -1):
        try:
            shot = pm.shoot(sol.z, sol.period / j)
        except OrbitError:
            continue
        d = shot.value - sol.z
        miss = math.sqrt(float(np.dot(d * w, d))) / amplitude
        before = closures.get(j)
        closed = miss < SUBPERIOD_TOL or (
            before is not None and miss < CLOSED_FINE and miss < before / SHRINK)
        if closed and not unsure:
            try:
                return correct(pm, sol.z, sol.period / j, sol.z, shot.d_dT,
                               max_steps=NEWTON_BUDGET, max_products=KRYLOV_BUDGET), {}, ""
            except OrbitError:
                continue
        if before is not None and not closed and miss < before / FELL:
            return sol, {}, (f"period T = {sol.period:.8g}; a shot over T / {j} misses by "
                             f"{before:.1e} of the amplitude at dt {coarse_dt:.4g} "
                             f"and {miss:.1e} at {pm.g.dt:.4g}: the miss falls with the "
                             "step, but not to where T / j would be certain")
        if coarse is None and miss < AMBIGUOUS:
            unsure[j] = miss
    return sol, unsure, ""


def state_from_window(t: np.ndarray, window: np.ndarray, g: Grid, at: float) -> np.ndarray:
    """The reduced state of core.orbit (m_y, s_x, s_y, u now; m_x - m_x(now) and m_y at
    the N delay-grid times before) at time ``at``, read from a sampled window by linear
    interpolation (its error, ~1e-5 of m_y's curvature at the sample step 0.01, is far
    inside Newton's reach)."""
    back = at - g.dt * np.arange(1, g.n_delay + 1)
    now = np.array([np.interp(at, t, row) for row in window])
    xi = np.interp(back, t, window[0]) - now[0]
    eta = np.interp(back, t, window[1])
    return np.concatenate((now[1:], xi, eta))


def orbit_maxima(m_y: np.ndarray) -> tuple[float, ...]:
    """The maxima of m_y over one period (sampled every step, first and last sample the
    same point); maxima of a plateau that no dip separates are one (core.returns
    .distinct_maxima)."""
    # start the period at its lowest point, so that no maximum straddles the section
    low = int(np.argmin(m_y[:-1]))
    y = np.concatenate((m_y[low:-1], m_y[:low + 1]))
    tt = np.arange(y.size, dtype=float)
    _, peak_y = distinct_maxima(tt, y, *find_peaks(tt, y), float(np.ptp(y)))
    return tuple(float(v) for v in peak_y)


def relabel(s: Summary, c: Certificate, p: Params) -> Summary:
    """The window's summary with the certified orbit's period and slips: period,
    period_count (in basic periods, core.returns) and maxima_per_period follow the orbit,
    and so do the regime (oscillatory after one basic period, complex after more) and its
    detail's words. ``settled`` stays the window's statement."""
    if not c.certified or s.attractor != "periodic" or not math.isfinite(c.period):
        return s
    basic = hopf_period(p.tau, p.F1)
    ratio = c.period / basic if basic > 0.0 else math.nan
    count = max(1, round(ratio)) if math.isfinite(ratio) else 1
    words = f"period-{count}, {maxima_words(c.slips)}" + (f", {ratio:.2f} T_H" if math.isfinite(ratio) else "")
    head = s.detail.split(";")[0]
    tail = s.detail[len(head):]
    detail = f"{words} (certified){tail}" if head.startswith("period-") else f"{s.detail}; {words} (certified)"
    peaks = s.peaks if len(s.peaks) == c.slips else sorted(c.maxima)
    return replace(s, regime="oscillatory" if count == 1 else "complex", detail=detail,
                   period=c.period, period_count=count, maxima_per_period=c.slips, peaks=list(peaks))
