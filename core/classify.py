"""Label the analysis window with the paper's regimes (Section 3) and measure it.

Regimes:
  sliding      the oscillation of m_y has died out: below AMPLITUDE_FLOOR, or decaying
               steadily across the sub-windows (near the Hopf curve decay rates are ~1e-4,
               so the oscillation is still visible at t = 1e5 but is going away);
  oscillatory  the peaks of m_y form one cluster (a period-1 limit cycle);
  complex      several clusters (period-n), or a continuum, which is called chaotic
               when lambda_max > 0 significantly (or, without lambda_max, when the
               Gottwald-Melbourne 0-1 test gives K > 0.5) and quasi-periodic otherwise;
  mixed        the window switches between quiet and oscillating stretches;
  unstable     the run blew up (core.recording.BLOWUP_BOUND).

The summary also reports the peak clusters (the points of a bifurcation diagram), the
period, the peak-to-peak amplitude, the dominant frequency and the drift of m_x.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from core.lyapunov import LyapunovEstimate

#: Peak-to-peak amplitude of m_y below which the window counts as at rest. A settled
#: sliding run leaves round-off only: we measured 0 to 1.5e-10 on the (b, tau) plane at
#: k = 6 and 12 (RK4, t_end = 2e4); limit cycles there have amplitudes of 1 and up.
AMPLITUDE_FLOOR = 1e-6
#: Sub-windows for the decay and switching tests.
N_SUBWINDOWS = 20
#: A steady decay counts as sliding when the sub-window amplitudes fall monotonically and
#: their fitted log-decay across the whole window exceeds DECAY_MIN (1%: at window 1000 a
#: rate of 1e-5/t, met within ~0.2% of k_H at tau = 10). Slow transients on attractors
#: stay far below it: the period-3 cycle at k = 22, tau = 10 drifts by 0.04% per window.
DECAY_MIN = 0.01
#: A sub-window is "quiet" when its amplitude is below this fraction of the largest one.
QUIET_FRACTION = 0.05
#: The peak sequence p_i is period-n when its lag-n return differences max|p_{i+n} - p_i|
#: are below RETURN_TOL times the amplitude, and n is the smallest lag within a factor
#: RETURN_MARGIN of the best lag. Measured at tau = 10, delta = 0.1 (RK4, t_end = 1e5):
#: settled cycles return to 1e-10 A; the period-2 orbit at k = 20 has lag-1 differences
#: of 1.6e-4 A (so a gap tolerance of 1e-3 A would merge its clusters) and lag-2 ones of
#: ~1e-6 A; the slowly drifting period-3 at k = 22 returns to 1e-5 A at lag 3. At small
#: tau and large k (period ~2) settled cycles return to ~5e-8 A (find_peaks).
RETURN_TOL = 1e-3
RETURN_MARGIN = 2.0
#: Return differences below this fraction of the amplitude are round-off (settled cycles
#: show ~1e-10 A), so every lag under it is equally good and the smallest one wins.
RETURN_NOISE = 1e-6
#: Longer periods than this are a continuum (quasi-periodic or chaotic), not period-n.
MAX_PERIOD = 16
#: Chaos needs lambda_max above 3 sigma and above this absolute value (1/time).
CHAOS_LAMBDA_MIN = 1e-3
#: At most this many peak values are kept for a continuum's bifurcation-diagram column.
MAX_PEAKS_KEPT = 64


@dataclass(frozen=True, slots=True)
class Summary:
    """What a run reports. Times and frequencies are in model time units."""

    regime: str
    detail: str
    amplitude: float                 # peak-to-peak of m_y over the window
    period: float                    # full period (n peak intervals for period-n); NaN if none
    period_count: int                # clusters: 0 at rest, n for period-n, -1 for a continuum
    peaks: list[float] = field(default_factory=list)  # cluster centres, or sampled continuum
    frequency: float = math.nan      # dominant frequency of m_y (cycles per time unit)
    drift: float = math.nan          # mean velocity of m_x over the window
    zero_one_k: float = math.nan     # 0-1 test statistic on the peak sequence (continua)


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


def peak_period(peaks: np.ndarray, amplitude: float, max_period: int = MAX_PERIOD) -> int:
    """The period n of the peak sequence (period-n orbit), or 0 if it has none <= max_period.

    r_n = max_i |p_{i+n} - p_i| measures how well the sequence repeats after n peaks.
    The period is the smallest n with r_n <= max(RETURN_MARGIN * min_m r_m,
    RETURN_NOISE * amplitude), provided that min_m r_m <= RETURN_TOL * amplitude. Unlike
    clustering the sorted values with a gap tolerance, this separates clusters closer than
    any fixed tolerance (period-2 just past the doubling) and tolerates clusters that still
    drift slowly.
    """
    if len(peaks) < 2 * max_period + 2:
        max_period = max(1, (len(peaks) - 2) // 2)
    r = np.array([np.max(np.abs(peaks[n:] - peaks[:-n])) for n in range(1, max_period + 1)])
    best = r.min()
    if not best <= RETURN_TOL * amplitude:
        return 0
    return int(np.nonzero(r <= max(RETURN_MARGIN * best, RETURN_NOISE * amplitude))[0][0]) + 1


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


def classify(t: np.ndarray, window: np.ndarray, blew_up: bool = False,
             lyap: LyapunovEstimate | None = None) -> Summary:
    """Classify an analysis window (rows m_x, m_y, ... sampled at times t)."""
    m_x, m_y = window[0], window[1]
    drift = _drift(t, m_x)
    if blew_up:
        return Summary("unstable", "blow-up", math.nan, math.nan, 0, [], math.nan, drift)
    amplitude = float(np.ptp(m_y)) if len(m_y) else math.nan
    if not amplitude >= AMPLITUDE_FLOOR:
        return Summary("sliding", "at rest", amplitude, math.nan, 0, [], math.nan, drift)
    frequency = dominant_frequency(t, m_y)

    amps, centres = subwindow_amplitudes(t, m_y)
    switches = _switches(amps < QUIET_FRACTION * amps.max())
    if switches >= 2:
        return Summary("mixed", f"{switches} switches", amplitude, math.nan, -1, [],
                       frequency, drift)
    rate = float(np.polyfit(centres, np.log(amps), 1)[0]) if np.all(amps > 0) else math.nan
    if rate * (t[-1] - t[0]) < -DECAY_MIN and np.all(np.diff(amps) < 0):
        return Summary("sliding", f"decaying at {rate:.2e}/t", amplitude, math.nan, 0, [],
                       frequency, drift)

    peak_t, peak_y = find_peaks(t, m_y)
    if len(peak_y) < 4:
        # too few maxima in the window to tell a period: report an oscillation of unknown
        # period rather than invent one
        return Summary("oscillatory", f"{len(peak_y)} peaks in window", amplitude, math.nan, 1,
                       sorted(float(v) for v in peak_y), frequency, drift)
    n = peak_period(peak_y, amplitude)
    if n:
        centres_y = sorted(float(peak_y[j::n].mean()) for j in range(n))
        mean_interval = float((peak_t[-1] - peak_t[0]) / (len(peak_t) - 1))
        regime = "oscillatory" if n == 1 else "complex"
        return Summary(regime, f"period-{n}", amplitude, n * mean_interval, n, centres_y,
                       frequency, drift)

    k01 = zero_one_test(peak_y)
    if lyap is not None and math.isfinite(lyap.value):
        err = lyap.error if math.isfinite(lyap.error) else 0.0
        chaotic = lyap.value > max(3.0 * err, CHAOS_LAMBDA_MIN)
    else:
        chaotic = k01 > 0.5
    kept = np.sort(peak_y)[np.linspace(0, len(peak_y) - 1, min(len(peak_y), MAX_PEAKS_KEPT)).astype(int)]
    return Summary("complex", "chaotic" if chaotic else "quasi-periodic", amplitude, math.nan, -1,
                   [float(v) for v in kept], frequency, drift, k01)
