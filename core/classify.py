"""Label a run with the paper's regimes (Section 3), from its dynamics, and measure it.

Regimes (the paper's five labels) and the attractor word beside them:
  sliding      at rest: at the fixed point (``fixed-point``), on a faster sliding branch
               (``fast-branch``, core.params.sliding_branches) or at a steady state off the
               branches that the noise carries (``variance-state``); or a linear
               oscillation near the fixed point (flag ``linear-transient``: the echoes of
               the kink of the constant history, core.solve), or a decaying oscillation;
               only where linear theory does not call that rest state unstable (below);
  oscillatory  an orbit that returns after one basic period (``periodic``), whatever its
               number of maxima per period (core.returns);
  complex      an orbit that returns after n >= 2 basic periods (``periodic``), or maxima
               that never return: chaos (``chaotic``: a positive exponent at 3 sigma,
               lambda_max or the spectrum's top one), a quasi-periodic orbit (``torus``:
               two zero exponents besides the shift's and the third clearly negative, from
               run --spectrum: core.spectrum), a band still moving (``unsettled``), or,
               without that evidence, ``undetermined`` (the reason in the detail; the 0-1
               test supports, never decides);
  mixed        the window switches between quiet and oscillating stretches;
  unstable     a runaway to a fast sliding branch far above the drive (``fast-branch``,
               beyond RUNAWAY_RATIO v), or a divergence of the equations (``divergent``;
               core.point first re-integrates a blow-up of an explicit scheme with the
               stiff-safe one, so what is left diverged there too);
  undetermined where the run is headed is not known (below).

**Linear theory first.** A window that rests at the fixed point, or oscillates in its
linear range, or decays toward it, is checked against the rest state's leading root
(core.rest_stability, with the run's noise). A positive root means the window has not
departed yet: the attractor is ``unstable-fixed-point``, flag ``not-departed``, and the
regime is where the run is headed, from the Hopf branch (core.heading): *oscillatory*
where it reaches the run's k with a stable cycle, else *undetermined*, the reason in the
detail. A root within NEUTRAL_TOL of 0 decides nothing (the detail says so), and a
negative root changes nothing: an oscillating window beside a stable rest state is a
coexisting cycle (the Hopf point is subcritical), not a contradiction.

``settled`` says whether the pattern was already there in the middle of the run (the
window that ends at t_end / 2, core.solve.Grid; the first half of the window when the run
has none): False for slow transients, modulations and growing or decaying oscillations.
The summary also reports the maxima of a return (the points of a bifurcation diagram),
the return time, the peak-to-peak amplitude, the dominant frequency and the drift of m_x.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np

from core.lyapunov import LyapunovEstimate
from core.params import Params, sliding_branches
from core.rest_stability import NEUTRAL_TOL, rest_exponent
from core.returns import Return, clusters, distinct_maxima, find_return, lag_defects
from core.stability import hopf_period, leading_exponent

if TYPE_CHECKING:  # core.spectrum loads core.solve, which imports this module
    from core.spectrum import Spectrum

#: Peak-to-peak amplitude of m_y (relative to max(1, |mean m_y|)) below which the window
#: counts as at rest. A settled sliding run leaves round-off only: we measured 0 to 1.5e-10
#: on the (b, tau) plane at k = 6 and 12 (RK4, t_end = 2e4).
AMPLITUDE_FLOOR = 1e-6
#: An oscillation about the fixed point whose amplitude and offset stay below this fraction
#: of y_nl = F'(v) / |3av - b| (the m_y at which the quadratic friction term of eq. 6b
#: equals the linear one; 0.55 at the defaults) is linear to that fraction: a transient of
#: the linearised system, not an attractor. At tau = 60, k = 6, delta = 1e-6 (0.4% above
#: k_H) the window holds the echoes of the history's kink, peak-to-peak 5.2e-6 (Euler,
#: t = 1e5), growing at the leading root's +1.3e-7 on time scales of 1e7; the smallest
#: limit cycles we saw have amplitudes of 1 and up. Such a window has not departed from
#: an unstable rest state: linear theory relabels it (_follow_theory).
LINEAR_FRACTION = 1e-2
#: Sub-windows for the decay and switching tests.
N_SUBWINDOWS = 20
#: A steady decay counts as sliding when the sub-window amplitudes fall monotonically and
#: their fitted log-decay across the whole window exceeds DECAY_MIN (1%: at window 1000 a
#: rate of 1e-5/t, met within ~0.2% of k_H at tau = 10). Slow transients on attractors
#: stay far below it: the three-maxima orbit at k = 22, tau = 10 drifts by 0.04% per window.
DECAY_MIN = 0.01
#: A sub-window is "quiet" when its amplitude is below this fraction of the largest one.
QUIET_FRACTION = 0.05
#: The pattern counts as settled when the maxima of a return and the return time in the
#: middle of the run equal those at the end to this fraction of the amplitude and of the
#: return time. Settled orbits agree to 1e-11 (k = 15, 17.2, tau = 10, RK4, t = 5e4 and
#: 1e5); at k = 20 the two maxima moved by 1.7e-3 A between those times: a modulation that
#: rotates with a period of ~1.5e5 and decays at ~1.5e-6/t (RK4, t_end = 2e4 to 2e6).
SETTLE_TOL = 1e-5
#: An alternation (a return after n >= 2 basic periods) decays when its defect at the
#: basic period fell by more than this factor between the middle and the end of the run.
ALTERNATION_DECAY = 0.5
#: A quasi-periodic orbit (torus) fills the same band of maxima in the middle and at the end
#: of the run: their lowest and highest maxima agree to this fraction of the amplitude.
TORUS_TOL = 1e-2
#: Chaos needs lambda_max (or the spectrum's top exponent) above 3 sigma and above this
#: absolute value (1/time). At k = 20, tau >= 60 the finite-time exponents are +1.2e-4 to
#: +1.5e-4 over 1.5e4 time units while the slips per delay still change (an independent
#: referee's runs): ten times below, a long transient or weak chaos that nothing decides there.
CHAOS_LAMBDA_MIN = 1e-3
#: At most this many peak values are kept for a continuum's bifurcation-diagram column.
MAX_PEAKS_KEPT = 64
#: Rest on a sliding branch counts as a runaway ("unstable") when the slope slides there
#: faster than RUNAWAY_RATIO times the drive v. The branches reached in the paper's planes
#: lie at v + m_y = 19-72 v (b, c, k planes: m_y = 1.84-7.14 at v = 0.1) or at
#: 1400-2000 v (Fig. 7, a = 0.03-0.04: m_y = 143-205); the ratio sits between them.
RUNAWAY_RATIO = 300.0
#: A rest state is on a branch when its m_y is within this fraction of the branch's: with
#: noise (d = 1e-4) the variance shifts the branch by ~1e-6 relative (measured on Fig. 6-9).
BRANCH_TOL = 1e-2
#: ... and at the fixed point when |m_y| is below this (the noise-driven drift of the
#: sliding state is m_y ~ -q d / (G (F' + k tau)) ~ 2e-6 at the defaults).
FIXED_POINT_TOL = 1e-3


@dataclass(frozen=True, slots=True)
class Summary:
    """What a run reports. Times and frequencies are in model time units."""

    regime: str
    detail: str
    amplitude: float                 # peak-to-peak of m_y over the window
    period: float                    # return time in state space; NaN if none
    period_count: int                # return time in basic periods; 0 at rest, -1 continuum
    peaks: list[float] = field(default_factory=list)  # maxima of a return, or sampled continuum
    frequency: float = math.nan      # dominant frequency of m_y (cycles per time unit)
    drift: float = math.nan          # mean velocity of m_x over the window
    zero_one_k: float = math.nan     # 0-1 test statistic on the peak sequence (continua)
    maxima_per_period: int = 0       # maxima of m_y in one return
    attractor: str = ""              # fixed-point, fast-branch, variance-state, periodic, ...
    settled: bool = True             # the pattern was there in the middle of the run too
    flags: tuple[str, ...] = ()      # linear-transient, slow-modulation, ... (core.point adds more)


def find_peaks(t: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Local maxima of y, refined by the quartic through each maximum and its two neighbours
    on each side (the parabola through three samples at the ends of the window).

    Why a quartic: the refinement error is the noise floor of peak_period. The parabola's
    error depends on where the peak falls between samples, and at small tau and large k
    (period ~2, sharp peaks) it reached 5e-6 of the amplitude at the window's sample step
    0.01: above RETURN_NOISE, so the few lags n whose n periods nearly repeat the sampling
    phase returned 100x better than lag 1, and settled cycles were called period-2, -8 or
    -12 (lone "complex" points across the (k, tau) plane at t_end = 2000). The quartic's
    error there is 4e-8 of the amplitude (tests/unit/test_classify.py).
    """
    if len(y) < 3:
        return np.zeros(0), np.zeros(0)
    left, mid, right = y[:-2], y[1:-1], y[2:]
    i = np.nonzero((mid > left) & (mid >= right))[0] + 1
    h = t[1] - t[0] if len(t) > 1 else 0.0
    off, top = _parabola_vertex(y[i - 1], y[i], y[i + 1])
    inner = (i >= 2) & (i <= len(y) - 3)
    j = i[inner]
    off[inner], top[inner] = _quartic_maximum(y[j - 2], y[j - 1], y[j], y[j + 1], y[j + 2],
                                              off[inner])
    return t[i] + off * h, top


def _parabola_vertex(y0: np.ndarray, y1: np.ndarray, y2: np.ndarray
                     ) -> tuple[np.ndarray, np.ndarray]:
    """Offset (in samples, within +-0.5) and value of the vertex of the parabola through
    (-1, y0), (0, y1), (1, y2)."""
    curv = y0 - 2.0 * y1 + y2
    with np.errstate(divide="ignore", invalid="ignore"):
        off = np.where(curv < 0.0, 0.5 * (y0 - y2) / curv, 0.0)
    off = np.clip(off, -0.5, 0.5)
    return off, y1 - 0.25 * (y0 - y2) * off


def _quartic_maximum(ym2: np.ndarray, ym1: np.ndarray, y0: np.ndarray, y1: np.ndarray,
                     y2: np.ndarray, start: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Offset (in samples, within +-1) and value of the maximum of the quartic through the
    five samples at -2..2, by Newton's method on its derivative from ``start``."""
    c1 = (ym2 - 8.0 * ym1 + 8.0 * y1 - y2) / 12.0
    c2 = (-ym2 + 16.0 * ym1 - 30.0 * y0 + 16.0 * y1 - y2) / 24.0
    c3 = (-ym2 + 2.0 * ym1 - 2.0 * y1 + y2) / 12.0
    c4 = (ym2 - 4.0 * ym1 + 6.0 * y0 - 4.0 * y1 + y2) / 24.0
    x = start.copy()
    for _ in range(4):  # from the parabola's vertex, 2 steps reach round-off; 4 to be safe
        slope = c1 + x * (2.0 * c2 + x * (3.0 * c3 + x * 4.0 * c4))
        curv = 2.0 * c2 + x * (6.0 * c3 + x * 12.0 * c4)
        with np.errstate(divide="ignore", invalid="ignore"):
            x = np.clip(x - np.where(curv < 0.0, slope / curv, 0.0), -1.0, 1.0)
    return x, y0 + x * (c1 + x * (c2 + x * (c3 + x * c4)))


def subwindow_amplitudes(t: np.ndarray, y: np.ndarray, n: int = N_SUBWINDOWS) -> tuple[np.ndarray, np.ndarray]:
    """Peak-to-peak amplitude of y in n equal sub-windows, with their centre times.

    Extrema are parabola-refined (peaks of y and of -y), so a settled limit cycle gives
    the same amplitude in every sub-window to ~1e-9 instead of the sampling jitter.
    """
    amps, centres = [], []
    for idx in np.array_split(np.arange(len(y)), n):
        if len(idx) < 3:
            continue
        ts, ys = t[idx], y[idx]
        _, hi = find_peaks(ts, ys)
        _, lo = find_peaks(ts, -ys)
        top = max(hi.max() if len(hi) else -np.inf, ys.max())
        bottom = min(-lo.max() if len(lo) else np.inf, ys.min())
        amps.append(top - bottom)
        centres.append(ts.mean())
    return np.array(amps), np.array(centres)


def power_spectrum(t: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """One-sided power spectrum of y (mean removed, Hann window, zero-padded to a length
    whose only prime factors are 2, 3 and 5); frequency in 1/time.

    Why the padding: a window of 1000 time units sampled every 0.01 has 100001 samples,
    11 x 9091, and numpy's FFT of a length with a large prime factor took 16 ms, against
    0.7 ms at 100000: most of the analysis of a run, and ~15% of a 64 x 64 diagram's
    wall time at t_end = 1e4."""
    if len(y) < 4:
        return np.zeros(0), np.zeros(0)
    h = t[1] - t[0]
    w = np.hanning(len(y))
    n = fast_fft_length(len(y))
    spec = np.abs(np.fft.rfft((y - y.mean()) * w, n)) ** 2
    freqs = np.fft.rfftfreq(n, h)
    return freqs, spec


def fast_fft_length(n: int) -> int:
    """The smallest m >= n whose only prime factors are 2, 3 and 5."""
    m = n
    while True:
        r = m
        for p in (2, 3, 5):
            while r % p == 0:
                r //= p
        if r == 1:
            return m
        m += 1


def dominant_frequency(t: np.ndarray, y: np.ndarray) -> float:
    """Frequency of the largest non-DC spectral peak, refined by a parabola in log power."""
    f, p = power_spectrum(t, y)
    if len(p) < 3 or not np.any(p[1:] > 0):
        return math.nan
    i = int(np.argmax(p[1:])) + 1
    if 1 <= i < len(p) - 1 and p[i - 1] > 0 and p[i + 1] > 0:
        a, b, c = np.log(p[i - 1]), np.log(p[i]), np.log(p[i + 1])
        denom = a - 2 * b + c
        off = 0.5 * (a - c) / denom if denom < 0 else 0.0
        return float(f[i] + off * (f[1] - f[0]))
    return float(f[i])


def zero_one_test(phi: np.ndarray, n_c: int = 100, seed: int = 0) -> float:
    """Gottwald-Melbourne 0-1 test for chaos (modified, correlation method; 2009).

    Returns K in [-1, 1]: near 1 for chaos, near 0 for regular dynamics. Needs a long
    sequence (>= ~100 values) to be meaningful; NaN for shorter ones.
    """
    phi = np.asarray(phi, dtype=float)
    n = len(phi)
    if n < 100 or np.ptp(phi) == 0.0:
        return math.nan
    phi = (phi - phi.mean()) / phi.std()
    rng = np.random.default_rng(seed)
    cs = rng.uniform(math.pi / 5, 4 * math.pi / 5, n_c)
    ncut = n // 10
    j = np.arange(1, n + 1)
    lags = np.arange(1, ncut + 1)
    ks = []
    for c in cs:
        p = np.cumsum(phi * np.cos(j * c))
        q = np.cumsum(phi * np.sin(j * c))
        m = np.array([np.mean((p[L:] - p[:-L]) ** 2 + (q[L:] - q[:-L]) ** 2) for L in lags])
        osc = phi.mean() ** 2 * (1 - np.cos(lags * c)) / (1 - np.cos(c))
        ks.append(np.corrcoef(lags, m - osc)[0, 1])
    return float(np.median(ks))


def _drift(t: np.ndarray, m_x: np.ndarray) -> float:
    if len(t) < 2:
        return math.nan
    return float((m_x[-1] - m_x[0]) / (t[-1] - t[0]))


def _switches(quiet: np.ndarray) -> int:
    return int(np.count_nonzero(quiet[1:] != quiet[:-1]))


def _rest(level: float, amplitude: float, drift: float, p: Params | None) -> Summary:
    """A window at rest: where it rests decides the label (see the module docstring)."""
    if abs(level) < FIXED_POINT_TOL:
        return Summary("sliding", "at rest", amplitude, math.nan, 0, [], math.nan, drift,
                       attractor="fixed-point")
    branch = next((r for r in (sliding_branches(p) if p else ()) if r != 0.0
                   and abs(level - r) <= BRANCH_TOL * abs(r)), None)
    if branch is None:
        return Summary("sliding", f"at rest, m_y = {level:.4g}", amplitude, math.nan, 0, [],
                       math.nan, drift, attractor="variance-state")
    assert p is not None
    if p.v + level > RUNAWAY_RATIO * p.v:
        return Summary("unstable", f"runaway to m_y = {level:.5g}", amplitude, math.nan, 0, [],
                       math.nan, drift, attractor="fast-branch")
    return Summary("sliding", f"fast branch, m_y = {level:.4g}", amplitude, math.nan, 0, [],
                   math.nan, drift, attractor="fast-branch")


def _follow_theory(s: Summary, p: Params | None, follow_branch: bool = True) -> Summary:
    """A window at, near or toward the fixed point beside the rest state's leading root
    (the module docstring's "Linear theory first"): unchanged where the root is negative,
    said to decide nothing within NEUTRAL_TOL of 0, and where it is positive the window
    has not departed: attractor ``unstable-fixed-point``, the regime where it is headed
    (core.heading)."""
    if p is None or s.attractor != "fixed-point":
        return s
    try:
        root = rest_exponent(p)
    except ArithmeticError as exc:
        return replace(s, detail=f"{s.detail}; linear theory undecided: {exc}")
    if abs(root) <= NEUTRAL_TOL:
        return replace(s, detail=f"{s.detail}; root {root:+.1e}/t is 0 to within "
                                 f"{NEUTRAL_TOL:.0e}: linear theory decides nothing")
    if root < 0.0:
        return s
    # imported here: the orbit kernels and scipy's sparse solvers it loads serve only the
    # rare window at an unstable rest state; a worker importing the classifier skips them
    from core.heading import Heading, heading
    head = heading(p) if follow_branch else Heading("undetermined", "the Hopf branch was not "
                                                                    "followed")
    return replace(s, regime=head.regime, attractor="unstable-fixed-point", settled=False,
                   detail=f"{s.detail}; not departed from the unstable rest state (root "
                          f"{root:+.2e}/t at d = {p.d:g}): {head.reason}",
                   flags=(*s.flags, "not-departed"))


def _early(t: np.ndarray, y: np.ndarray, mid_t: np.ndarray | None, mid: np.ndarray | None
           ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(early t, early m_y, late t, late m_y): the middle window against the end window,
    or the two halves of the end window when the run has no middle window."""
    if mid_t is not None and mid is not None and len(mid_t) >= len(t) // 2 and len(mid_t) > 2:
        return mid_t, mid[1], t, y
    h = len(t) // 2
    return t[:h], y[:h], t[h:], y[h:]


def _linear(t: np.ndarray, y: np.ndarray, early: tuple, amplitude: float, drift: float,
            p: Params) -> Summary:
    """An oscillation within the linear range of the fixed point: its growth rate between
    the early and late windows beside the leading root of the linearisation."""
    et, ey, lt, ly = early
    a_early, a_late = float(np.ptp(ey)), float(np.ptp(ly))
    span = float(lt.mean() - et.mean())
    rate = math.log(a_late / a_early) / span if a_early > 0 and a_late > 0 and span > 0 else math.nan
    root = leading_exponent(p)
    return Summary("sliding", f"linear {rate:+.1e}/t, root {root:+.1e}", amplitude, math.nan, 0, [],
                   dominant_frequency(t, y), drift, attractor="fixed-point", settled=False,
                   flags=("linear-transient",))


def _settled(early_peaks: tuple[np.ndarray, np.ndarray], amplitude: float, basic: float, ret: Return,
             late_peaks: list[float], step: float = 0.0) -> bool:
    """Whether the early window returns as the late one, with the same maxima and time."""
    pt, py = early_peaks
    if len(py) < 4:
        return False
    then = find_return(pt, py, amplitude, basic, step)
    if then is None or then.maxima != ret.maxima:
        return False
    moved = max(abs(a - b) for a, b in zip(clusters(py, then.maxima), late_peaks, strict=True))
    return moved <= SETTLE_TOL * amplitude and abs(then.time - ret.time) <= SETTLE_TOL * ret.time


def maxima_words(n: int) -> str:
    """"1 maximum", "3 maxima": the maxima of a return, in a detail."""
    return f"{n} maximum" if n == 1 else f"{n} maxima"


def _periodic(peak_t: np.ndarray, peak_y: np.ndarray, ret: Return, early_peaks: tuple[np.ndarray, np.ndarray],
              amplitude: float, basic: float, frequency: float, drift: float, step: float = 0.0) -> Summary:
    """An orbit that returns: oscillatory after one basic period, complex after n >= 2,
    unless the alternation that makes it n is dying out (step: the window's sample step,
    core.returns.lag_defects)."""
    n = ret.maxima
    late = clusters(peak_y, n)
    settled = _settled(early_peaks, amplitude, basic, ret, late, step)
    flags: tuple[str, ...] = () if settled else ("slow-modulation",)
    count = ret.count or 1
    per = n // count if count > 1 and n % count == 0 else 0
    if count > 1 and per and not settled:
        # the defect of the return after one basic period, then and now
        ept, epy = early_peaks
        q_then = lag_defects(ept, epy, amplitude, per, step)[-1] if len(epy) > 2 * per + 2 else math.nan
        q_now = lag_defects(peak_t, peak_y, amplitude, per, step)[-1]
        if q_now < ALTERNATION_DECAY * q_then:
            return Summary("oscillatory", f"alternation decaying {q_then:.1e} -> {q_now:.1e}",
                           amplitude, ret.time / count, 1, clusters(peak_y, per), frequency, drift,
                           maxima_per_period=per, attractor="periodic", settled=False,
                           flags=("decaying-alternation",))
    ratio = f", {ret.ratio:.2f} T_H" if math.isfinite(ret.ratio) else ""
    if count == 1:
        return Summary("oscillatory", f"period-1, {maxima_words(n)}{ratio}", amplitude, ret.time, 1, late,
                       frequency, drift, maxima_per_period=n, attractor="periodic",
                       settled=settled, flags=flags)
    return Summary("complex", f"period-{count}, {maxima_words(n)}{ratio}", amplitude, ret.time, count, late,
                   frequency, drift, maxima_per_period=n, attractor="periodic", settled=settled,
                   flags=flags)


def _continuum(peak_y: np.ndarray, early_peaks: tuple[np.ndarray, np.ndarray], amplitude: float,
               frequency: float, drift: float, lyap: LyapunovEstimate | None,
               spectrum: Spectrum | None = None) -> Summary:
    """Maxima that never return: chaos or a torus where the exponents show it, a slow
    transient (unsettled) where the band of maxima still moves, else undetermined."""
    k01 = zero_one_test(peak_y)
    kept = np.sort(peak_y)[np.linspace(0, len(peak_y) - 1, min(len(peak_y), MAX_PEAKS_KEPT)).astype(int)]
    _, epy = early_peaks
    same_band = len(epy) > 0 and (abs(epy.min() - peak_y.min()) <= TORUS_TOL * amplitude
                                  and abs(epy.max() - peak_y.max()) <= TORUS_TOL * amplitude)
    attractor, detail = _continuum_attractor(same_band, k01, lyap, spectrum)
    return Summary("complex", detail, amplitude, math.nan, -1, [float(v) for v in kept], frequency,
                   drift, k01, maxima_per_period=0, attractor=attractor, settled=same_band,
                   flags=() if same_band else ("slow-modulation",))


def _continuum_attractor(same_band: bool, k01: float, lyap: LyapunovEstimate | None,
                         spectrum: Spectrum | None) -> tuple[str, str]:
    """(attractor, detail) of a continuum. Chaos needs a positive exponent significant at
    3 sigma (the spectrum's top one, else lambda_max); a torus two zero exponents besides
    the shift's and the third clearly negative (core.spectrum.evidence), and a band of
    maxima that stays; the 0-1 test only supports either. Without that evidence the
    attractor is undetermined, the reason in the detail. The details hold no numbers (the
    exponents and K are fields of their own): the report counts runs by their detail."""
    from core.spectrum import evidence, is_zero
    support = ("; the 0-1 test suggests chaos (K > 0.5), which only a positive exponent at 3 "
               "sigma shows" if k01 > 0.5 else "")
    if spectrum is not None and spectrum.values:
        ev = evidence(spectrum, CHAOS_LAMBDA_MIN)
        if ev.chaotic:
            return "chaotic", "chaotic"
        if not same_band:
            return "unsettled", "no return, band still moving"
        if ev.torus:
            return "torus", "quasi-periodic"
        return "undetermined", f"no return: {ev.reason}{support}"
    # without an error bar (a run too short for two blocks) nothing is significant
    if (lyap is not None and math.isfinite(lyap.value) and math.isfinite(lyap.error)
            and lyap.value > max(3.0 * lyap.error, CHAOS_LAMBDA_MIN)):
        return "chaotic", "chaotic"
    if not same_band:
        return "unsettled", "no return, band still moving"
    if lyap is None or not math.isfinite(lyap.value):
        return "undetermined", ("no return: chaos needs a positive exponent, quasi-periodic "
                                f"two zero exponents: run --spectrum 3{support}")
    if lyap.value > 0.0 and not is_zero(lyap.value, lyap.error):
        return "undetermined", ("no return: lambda_max positive but not above 3 sigma and "
                                f"{CHAOS_LAMBDA_MIN:g}: near-neutral exponents: a slow "
                                f"transient?{support}")
    return "undetermined", ("no return: quasi-periodic needs two zero exponents: run "
                            f"--spectrum 3{support}")


def _spectrum_note(s: Summary, spectrum: Spectrum | None) -> Summary:
    """A periodic window beside a spectrum with more zero exponents than the flow's: an
    orbit with near-neutral directions, or a slow transient (the multi-slip states at
    tau = 10: 2(n - 1) of them besides the flow's, on their way to equally spaced n-slip
    orbits over ~1e6 time units)."""
    if spectrum is None or not spectrum.values or s.attractor != "periodic":
        return s
    from core.spectrum import evidence
    extra = evidence(spectrum, CHAOS_LAMBDA_MIN).neutral - 1
    if extra <= 0:
        return s
    return replace(s, detail=f"{s.detail}; {extra} near-neutral exponent"
                             f"{'s' if extra > 1 else ''} besides the flow's: a slow transient?")


def classify(t: np.ndarray, window: np.ndarray, blew_up: bool = False,
             lyap: LyapunovEstimate | None = None, mid_t: np.ndarray | None = None,
             mid: np.ndarray | None = None, p: Params | None = None,
             follow_branch: bool = True, spectrum: Spectrum | None = None) -> Summary:
    """Classify a run from its analysis window (rows m_x, m_y, ... sampled at times t), the
    window that ends at the middle of the run (mid_t, mid; may be empty) and its parameters
    p (for the basic period, the branches and the linear range; without them those tests
    are skipped).

    follow_branch: at an unstable rest state, follow the Hopf branch to name where the run
    is headed (core.heading, seconds); False leaves it undetermined, for a caller that
    finds out by simulation (core.hysteresis kicks the state and classifies where it
    lands).

    spectrum: the run's top Lyapunov exponents (core.spectrum, run --spectrum), the
    evidence for a torus or chaos where the window has no return."""
    m_x, m_y = window[0], window[1]
    drift = _drift(t, m_x)
    if blew_up:
        return Summary("unstable", "diverged", math.nan, math.nan, 0, [], math.nan, drift,
                       attractor="divergent")
    amplitude = float(np.ptp(m_y)) if len(m_y) else math.nan
    level = float(np.mean(m_y)) if len(m_y) else math.nan
    if not amplitude >= AMPLITUDE_FLOOR * max(1.0, abs(level)):
        return _follow_theory(_rest(level, amplitude, drift, p), p, follow_branch)
    early = _early(t, m_y, mid_t, mid)
    if p is not None and p.F1 > 0.0 and p.q != 0.0:
        y_nl = p.F1 / abs(p.q)
        if amplitude < LINEAR_FRACTION * y_nl and abs(level) < LINEAR_FRACTION * y_nl:
            return _follow_theory(_linear(t, m_y, early, amplitude, drift, p), p, follow_branch)
    frequency = dominant_frequency(t, m_y)

    amps, centres = subwindow_amplitudes(t, m_y)
    switches = _switches(amps < QUIET_FRACTION * amps.max())
    if switches >= 2:
        return Summary("mixed", f"{switches} switches", amplitude, math.nan, -1, [],
                       frequency, drift, attractor="unsettled", settled=False)
    rate = float(np.polyfit(centres, np.log(amps), 1)[0]) if np.all(amps > 0) else math.nan
    if rate * (t[-1] - t[0]) < -DECAY_MIN and np.all(np.diff(amps) < 0):
        return _follow_theory(Summary("sliding", f"decaying at {rate:.2e}/t", amplitude, math.nan, 0,
                                      [], frequency, drift, attractor="fixed-point", settled=False,
                                      flags=("decaying",)), p, follow_branch)

    peak_t, peak_y = distinct_maxima(t, m_y, *find_peaks(t, m_y), amplitude)  # a plateau's: one
    if len(peak_y) < 4:
        # too few maxima in the window to tell a return: an oscillation of unknown period
        return Summary("oscillatory", f"{len(peak_y)} peaks in window", amplitude, math.nan, 1,
                       sorted(float(v) for v in peak_y), frequency, drift,
                       maxima_per_period=len(peak_y), attractor="periodic", settled=False)
    basic = hopf_period(p.tau, p.F1) if p is not None else math.nan
    step = float(t[1] - t[0])  # the sample step: a flat maximum's timing noise (core.returns)
    ret = find_return(peak_t, peak_y, amplitude, basic, step)
    early_peaks = distinct_maxima(early[0], early[1], *find_peaks(early[0], early[1]), amplitude)
    if ret is not None:
        return _spectrum_note(_periodic(peak_t, peak_y, ret, early_peaks, amplitude, basic,
                                        frequency, drift, step), spectrum)
    return _continuum(peak_y, early_peaks, amplitude, frequency, drift, lyap, spectrum)
