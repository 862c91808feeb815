"""When an orbit comes back: return times measured on the sequence of its maxima.

The maxima of m_y (times t_i, heights p_i; core.classify.find_peaks) are a Poincaré
section of the flow (dm_y/dt = 0, falling). An orbit that returns after n maxima repeats
both their heights and their spacing at lag n: the defect

    q_n = max( max_i |p_{i+n} - p_i| / A ,  max_i |(t_{i+n} - t_i) - T_n| / T_n ),

(a spacing defect below TIME_NOISE, or below a tenth of the sample step, counts as 0:
the timing noise of a flat maximum),
with A the peak-to-peak amplitude of m_y and T_n the mean lag-n time, is then at the level
of round-off. Heights alone are not enough: along tau = 10 at k = 17.2-20 the orbit has two
maxima per period of almost equal height (2.2128 and 2.2133 at k = 20, RK4, t = 1e5:
lag-1 height defect 2e-4 A) but spacings of 2.86 and 7.51, a lag-1 timing defect of 0.45.
Counting height clusters called that orbit "period-2"; it returns after one period of
10.36 (lag-2 defect 3e-7) and has no better return at 2 or 3 periods.

The return time is a time, so it is counted in units of the *basic period* of the model's
oscillation, the period 2 pi / omega_H born on the first Hopf branch at this tau and F'
(core.stability.hopf_period): period-1 orbits return after 0.93-1.02 of it in every
regime we measured, so a return after about 2 of it is a period doubling.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: The orbit returns at lag n when q_n <= RETURN_TOL. Settled orbits return to 1e-12 A in
#: heights and 1e-7 in spacing (k = 15, 17.2 at tau = 10, RK4); orbits that are still slowly
#: changing (k = 20-23, tau = 10) to 3e-7-5e-5; lags that are not a return have defects of
#: 6e-3 and more (k = 23: the three maxima differ by 7e-3 A, their spacings by 20-40%).
RETURN_TOL = 1e-3
#: Among the lags that return, the smallest one within RETURN_MARGIN of the best defect
#: (or below RETURN_NOISE, where all defects are round-off) wins: multiples of the
#: period return as well as the period, a little worse where the orbit drifts.
RETURN_MARGIN = 2.0
RETURN_NOISE = 1e-6
#: Spacing defects below this are timing noise and count as 0: the time of a flat maximum
#: is uncertain (the square wave at k = 6, b = 15.5, tau = 21.3, RK4: 1.7e-6 at every lag,
#: against height defects of 7e-11); settled rounded maxima show 2e-8-7e-8.
TIME_NOISE = 1e-5
#: ... and so do spacing defects below this fraction of the window's sample step (in
#: absolute time): the time of a flat maximum is found to a fraction of a sample, which
#: does not shrink with the period. At large b the flat-topped maxima's times scatter with
#: the sampling phase (sample step 0.01, Euler dt 1e-3, t_end 2e4): 0.009 samples at
#: b = 15, k = 12, tau = 6; 0.024 at b = 17, k = 10, tau = 7; 0.038 at b = 18, k = 12,
#: tau = 10, a spacing defect of 1.3e-5-3.4e-5 of the period at lag 1, where the heights
#: repeat to 2e-8-1.6e-7 A and an independent RK4 at dt / 2 sees one maximum a period,
#: equally spaced (tests/integration/test_minimal_period.py). Above TIME_NOISE, lag 1 was
#: rejected, and the lag whose n periods happened to repeat the sampling phase better was
#: called period-2, -3 or -4. Genuine alternations of the spacing are 100 times coarser
#: than the margin left (2.86 against 7.51 at tau = 10, k = 20: 465 samples).
SAMPLE_TIME_NOISE = 0.1
#: Longer returns than this many maxima are not told from a continuum (quasi-periodic or
#: chaotic); the three-hump orbits at tau = 10 need 3, the square waves at large tau ~6.
MAX_MAXIMA = 16

#: Maxima not separated by a dip deeper than this fraction of the amplitude are one
#: maximum (the highest of them): a plateau's round-off ripple, not slips. On the
#: stick phase of the square wave at k = 7, tau = 60 (RK4, dt 0.01, t_end 2e4) m_y stays
#: at -0.590062 with ~200 local maxima a period, equal to 1.3e-12 A: the window was called
#: "no return, band still moving" (on the RK4 orbit through it, 154 "slips" a period).
#: Refined maxima of distinct slips are found to 4e-8 A (core.classify.find_peaks), and
#: distinct maxima dip far below each other (tau = 10, k = 20, RK4: by 0.997 A between
#: the two maxima 2e-4 A apart in height).
PLATEAU_TOL = 1e-8


@dataclass(frozen=True, slots=True)
class Return:
    """How an orbit returns: after ``maxima`` maxima and ``time`` time units, with the
    defect of that return (0: exact); ``count`` is the return time in basic periods (0 if
    the basic period is unknown) and ``ratio`` the unrounded one."""

    maxima: int
    time: float
    defect: float
    count: int
    ratio: float


def lag_defects(t_peaks: np.ndarray, peaks: np.ndarray, amplitude: float,
                max_lag: int = MAX_MAXIMA, step: float = 0.0) -> np.ndarray:
    """q_n for n = 1..max_lag (fewer if the sequence is short): see the module docstring.
    ``step``: the sample step of the series the maxima were found on (0: unknown)."""
    max_lag = min(max_lag, max(1, (len(peaks) - 2) // 2))
    out = np.empty(max_lag)
    for n in range(1, max_lag + 1):
        heights = np.max(np.abs(peaks[n:] - peaks[:-n])) / amplitude
        spans = t_peaks[n:] - t_peaks[:-n]
        mean = spans.mean()
        spread = np.max(np.abs(spans - mean))
        noise = spread <= SAMPLE_TIME_NOISE * step or spread <= TIME_NOISE * mean
        out[n - 1] = max(heights, 0.0 if noise else spread / mean)
    return out


def find_return(t_peaks: np.ndarray, peaks: np.ndarray, amplitude: float,
                basic_period: float, step: float = 0.0) -> Return | None:
    """The first return of the maxima sequence, or None if it has none within MAX_MAXIMA
    (``step``: the sample step the maxima were found on, lag_defects)."""
    q = lag_defects(t_peaks, peaks, amplitude, step=step)
    best = float(q.min())
    if not best <= RETURN_TOL:
        return None
    n = int(np.nonzero(q <= max(RETURN_MARGIN * best, RETURN_NOISE))[0][0]) + 1
    time = float(np.mean(t_peaks[n:] - t_peaks[:-n]))
    ratio = time / basic_period if basic_period > 0.0 else math.nan
    count = 0
    if math.isfinite(ratio):
        count = max(1, round(ratio))
    return Return(n, time, float(q[n - 1]), count, ratio)


def clusters(peaks: np.ndarray, n: int) -> list[float]:
    """The n maxima of one return, as the means over the window, ascending."""
    return sorted(float(peaks[j::n].mean()) for j in range(n))


def distinct_maxima(t: np.ndarray, y: np.ndarray, peak_t: np.ndarray, peak_y: np.ndarray,
                    amplitude: float) -> tuple[np.ndarray, np.ndarray]:
    """The maxima (peak_t, peak_y of the samples y at times t, core.classify.find_peaks)
    with those that no dip deeper than PLATEAU_TOL of the amplitude separates merged into
    the highest of them: maxima equal to round-off on a plateau are one maximum."""
    if len(peak_t) < 2 or len(t) < 2:
        return peak_t, peak_y
    at = np.clip(np.rint((peak_t - t[0]) / (t[1] - t[0])).astype(np.int64), 0, len(y) - 1)
    dips = np.minimum.reduceat(y, at)[:-1] if np.all(np.diff(at) > 0) else None
    if dips is None:
        return peak_t, peak_y
    floor = PLATEAU_TOL * amplitude
    keep_t, keep_y = [peak_t[0]], [peak_y[0]]
    for j in range(1, len(peak_t)):
        if dips[j - 1] > min(keep_y[-1], peak_y[j]) - floor:   # no dip between: one maximum
            if peak_y[j] > keep_y[-1]:
                keep_t[-1], keep_y[-1] = peak_t[j], peak_y[j]
            continue
        keep_t.append(peak_t[j])
        keep_y.append(peak_y[j])
    return np.array(keep_t), np.array(keep_y)
