"""The classifier on windows whose answer is known by construction."""

from __future__ import annotations

import math

import numpy as np
import pytest

from core.classify import (
    classify,
    dominant_frequency,
    fast_fft_length,
    find_peaks,
    zero_one_test,
)
from core.lyapunov import LyapunovEstimate
from core.params import Params
from core.point import run_point
from core.returns import RETURN_NOISE, find_return
from core.solve import SolverSettings
from core.spectrum import Spectrum

T = np.arange(0.0, 1000.0, 0.01)


def window(y: np.ndarray, drift: float = 0.0) -> np.ndarray:
    w = np.zeros((5, len(y)))
    w[0] = drift * T
    w[1] = y
    return w


def test_constant_window_is_sliding_at_rest_with_its_drift():
    s = classify(T, window(np.full_like(T, 4e-6), drift=4e-6))
    assert s.regime == "sliding" and s.detail == "at rest"
    assert s.drift == pytest.approx(4e-6)


def test_slow_decay_near_hopf_is_sliding():
    y = 0.3 * np.exp(-1e-4 * T) * np.sin(2 * np.pi * 0.1 * T)   # decay rate 1e-4
    s = classify(T, window(y))
    assert s.regime == "sliding" and s.detail.startswith("decaying")


def test_steady_cycle_is_oscillatory_with_its_period_and_frequency():
    def cycle(t):
        return np.sin(2 * np.pi * t / 10.5) + 0.3 * np.sin(4 * np.pi * t / 10.5 + 1.0)

    y = cycle(T)
    s = classify(T, window(y))
    true_max = cycle(np.linspace(0.0, 10.5, 2_000_001)).max()   # sampled max misses ~3e-6
    assert s.regime == "oscillatory" and s.period_count == 1
    assert s.period == pytest.approx(10.5, rel=1e-4)
    assert s.frequency == pytest.approx(1 / 10.5, rel=2e-3)
    assert len(s.peaks) == 1 and s.peaks[0] == pytest.approx(true_max, abs=1e-7)


def test_two_close_maxima_with_equal_spacing_are_period_2():
    # alternate peak heights 1.0 and 1.0003 (a gap of 1.5e-4 of the amplitude), evenly
    # spaced: a period doubling of a cycle of period 5, i.e. 2 basic periods of 5
    y = np.sin(2 * np.pi * T / 5.0) * (1 + 1.5e-4 * np.cos(np.pi * T / 5.0 + 0.1))
    ret = find_return(*find_peaks(T, y), float(np.ptp(y)), basic_period=5.0)
    assert ret is not None and (ret.maxima, ret.count) == (2, 2)
    assert ret.time == pytest.approx(10.0, rel=1e-3)


def test_a_period_1_orbit_with_three_maxima_is_oscillatory():
    # one return every 10 time units with three maxima of different heights at uneven
    # times (the orbits at k = 22-24, tau = 10): counting height clusters called it
    # period-3; it returns after one basic period
    def orbit(t):
        ph = 2 * np.pi * t / 10.0
        return np.sin(ph) + 0.5 * np.sin(3 * ph + 0.4) + 0.2 * np.sin(2 * ph)

    y = orbit(T)
    s = classify(T[T >= 500], window(y)[:, T >= 500], mid_t=T[T < 500], mid=window(y)[:, T < 500],
                 p=_with_basic_period(10.3))
    assert (s.regime, s.period_count, s.maxima_per_period) == ("oscillatory", 1, 3), s
    assert s.period == pytest.approx(10.0, rel=1e-6) and s.settled


def _with_basic_period(period: float) -> Params:
    """Parameters whose Hopf period (the basic period) is ``period``, with F' = 3.456."""
    from core.stability import hopf_period
    lo, hi = 0.1, 100.0
    p = Params()
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if hopf_period(mid, p.F1) < period else (lo, mid)
    return p.with_(tau=lo)


def test_a_decaying_alternation_is_not_complex():
    # maxima alternating by 1e-3 A in the middle of the run and by 1e-4 A at its end, at
    # equal spacing (a transient toward the period-1 orbit): oscillatory, not period-2
    def alternation(t, size):
        return np.sin(2 * np.pi * t / 5.0) * (1 + size * np.cos(np.pi * t / 5.0 + 0.1))

    p = _with_basic_period(5.0)
    s = classify(T, window(alternation(T, 1e-4)), mid_t=T, mid=window(alternation(T, 1e-3)), p=p)
    assert s.regime == "oscillatory" and s.period_count == 1 and not s.settled, s
    assert "decaying-alternation" in s.flags
    # the same alternation, unchanged since the middle of the run, is a period doubling
    s = classify(T, window(alternation(T, 1e-3)), mid_t=T, mid=window(alternation(T, 1e-3)), p=p)
    assert s.regime == "complex" and s.period_count == 2 and s.settled, s


QUASI = np.sin(2 * np.pi * T / 10.0) + 0.2 * np.sin(2 * np.pi * T / (10.0 * math.sqrt(2)))


def _spectrum(*pairs: tuple[float, float]) -> Spectrum:
    return Spectrum(tuple(v for v, _ in pairs), tuple(e for _, e in pairs), 5e4)


def test_quasi_periodic_window_is_a_torus_only_with_two_zero_exponents():
    """Before: a continuum whose band stays was a torus on lambda_max ~ 0 alone ("torus,
    settled" at k = 20, tau >= 60 was not shown). Now the spectrum decides."""
    s = classify(T, window(QUASI), lyap=LyapunovEstimate(1e-5, 2e-5, 5e4, 20))
    assert s.regime == "complex" and s.period_count == -1 and s.settled
    assert s.attractor == "undetermined" and "run --spectrum 3" in s.detail
    torus = _spectrum((1e-5, 2e-5), (-2e-5, 3e-5), (-0.04, 1e-3))
    s = classify(T, window(QUASI), lyap=LyapunovEstimate(1e-5, 2e-5, 5e4, 20), spectrum=torus)
    assert s.attractor == "torus" and s.detail == "quasi-periodic" and s.settled


def test_near_neutral_third_exponent_is_no_torus():
    """Two zero exponents and a third within its errors of 0: a slow transient, perhaps
    (the multi-slip states at tau = 10 have 2(n - 1) such exponents besides the flow's)."""
    slow = _spectrum((1e-5, 2e-5), (-2e-5, 3e-5), (-4e-5, 3e-5))
    s = classify(T, window(QUASI), spectrum=slow)
    assert s.attractor == "undetermined" and "near-neutral exponents: a slow transient?" in s.detail


def test_weak_positive_exponent_is_undetermined_not_chaos():
    """The referee's k = 20, tau >= 60: finite-time exponents +1.2e-4 to +1.5e-4. Below
    CHAOS_LAMBDA_MIN, and the 0-1 test alone does not decide."""
    s = classify(T, window(QUASI), lyap=LyapunovEstimate(1.3e-4, 1e-5, 1.5e4, 20))
    assert s.attractor == "undetermined" and "slow transient?" in s.detail
    weak = _spectrum((1.3e-4, 1e-5), (-2e-5, 3e-5), (-0.04, 1e-3))
    assert classify(T, window(QUASI), spectrum=weak).attractor == "undetermined"


def test_the_zero_one_test_alone_is_no_chaos(monkeypatch):
    """Before: without lambda_max a 0-1 statistic above 0.5 named the continuum chaotic."""
    import sys
    monkeypatch.setattr(sys.modules["core.classify"], "zero_one_test", lambda phi: 0.97)
    s = classify(T, window(QUASI))
    assert s.attractor == "undetermined" and "the 0-1 test suggests chaos (K > 0.5)" in s.detail


def test_significant_positive_lambda_on_a_continuum_is_chaos():
    s = classify(T, window(QUASI), lyap=LyapunovEstimate(0.02, 1e-3, 5e4, 20))
    assert s.attractor == "chaotic" and s.detail == "chaotic"
    s = classify(T, window(QUASI), spectrum=_spectrum((0.02, 1e-3), (0.0, 1e-4), (-0.1, 1e-3)))
    assert s.attractor == "chaotic" and s.detail == "chaotic"


def test_a_periodic_window_beside_extra_zero_exponents_says_so():
    y = np.sin(2 * np.pi * T / 10.0)
    p = _with_basic_period(10.0)
    flat = _spectrum((0.0, 1e-5), (-1e-5, 2e-5), (2e-5, 2e-5), (-0.05, 1e-3))
    s = classify(T, window(y), mid_t=T, mid=window(y), p=p, spectrum=flat)
    assert s.attractor == "periodic" and "2 near-neutral exponents besides the flow's" in s.detail
    s = classify(T, window(y), mid_t=T, mid=window(y), p=p,
                 spectrum=_spectrum((0.0, 1e-5), (-0.04, 1e-3)))
    assert "near-neutral" not in s.detail


def test_switching_between_quiet_and_oscillating_is_mixed():
    envelope = ((T // 150) % 2 == 1).astype(float)              # quiet, burst, quiet, ...
    y = 1e-6 + envelope * np.sin(2 * np.pi * T / 3.0)
    s = classify(T, window(y))
    assert s.regime == "mixed"


def test_blow_up_is_unstable():
    s = classify(T[:0], np.zeros((5, 0)), blew_up=True)
    assert s.regime == "unstable"


def test_peak_refinement_is_accurate():
    t = np.arange(0.0, 50.0, 0.05)
    pt, py = find_peaks(t, np.cos(2 * np.pi * (t - 0.013) / 7.0))
    assert np.allclose(py, 1.0, atol=1e-5) and np.allclose(pt % 7.0, 0.013, atol=1e-3)


def test_peak_refinement_error_is_below_the_return_noise_floor():
    # A sharp periodic peak (period 1.708 at the window's sample step 0.01, like the
    # cycles at small tau and large k; off the sample grid, so the peaks fall at every
    # phase between two samples): every peak must come out the same to well below
    # RETURN_NOISE. The parabola's spread here is 3.4e-6, the quartic's 2.7e-8.
    t = np.arange(0.0, 500.0, 0.01)
    y = np.exp(5.0 * np.cos(2 * np.pi * t / 1.70813))
    _, py = find_peaks(t, y)
    assert np.ptp(py) < 0.05 * RETURN_NOISE * np.ptp(y)


def test_settled_cycle_at_small_tau_is_period_one():
    # A point of the 64 x 64 (k, tau) lattice of benchmarks/bench_adaptive.py: a settled
    # period-1 cycle (period 1.71). With the parabola's peak refinement its peaks repeated
    # best after 12 periods, and it was called complex (period-12).
    r = run_point(Params(k=2 + 45 * 18 / 63, tau=0.5 + 5 * 9.5 / 63), SolverSettings(method="rk4", dt=0.01,
                                                               t_end=2000.0, window=500.0,
                                                               lyap=False))
    assert (r.summary.regime, r.summary.period_count, r.summary.maxima_per_period) == ("oscillatory", 1, 1)


def test_returns_of_sequences():
    def maxima(heights):
        ret = find_return(np.arange(len(heights), dtype=float), heights, 1.0, 1.0)
        return ret.maxima if ret else 0

    assert maxima(np.tile([1.0, 1.2], 50)) == 2
    assert maxima(np.tile([1.0, 1.1, 1.3], 50)) == 3
    assert maxima(np.full(100, 2.0) + 1e-12 * np.arange(100)) == 1
    rng = np.random.default_rng(0)
    assert maxima(rng.uniform(0, 1, 200)) == 0


def test_zero_one_test_separates_chaos_from_order():
    x, seq = 0.3, []
    for _ in range(2000):                       # logistic map at r = 3.97: chaotic
        x = 3.97 * x * (1 - x)
        seq.append(x)
    assert zero_one_test(np.array(seq)) > 0.8
    n = np.arange(2000)                         # quasi-periodic sequence
    assert abs(zero_one_test(np.sin(2 * np.pi * n * (math.sqrt(5) - 1) / 2 * 0.37))) < 0.2


def test_fft_length_is_the_next_5_smooth_number():
    def smooth(m: int) -> bool:
        for p in (2, 3, 5):
            while m % p == 0:
                m //= p
        return m == 1
    for n in (4, 7, 100001, 123457):
        m = fast_fft_length(n)
        assert m >= n and smooth(m) and not any(smooth(x) for x in range(n, m))


def test_dominant_frequency_of_a_window_of_awkward_length():
    # 100001 samples (11 x 9091): the spectrum is zero-padded to 101250 points
    t = np.arange(100001) * 0.01
    assert dominant_frequency(t, np.sin(2 * np.pi * 0.0951 * t)) == pytest.approx(0.0951,
                                                                                  rel=1e-3)


def test_dominant_frequency():
    assert dominant_frequency(T, np.sin(2 * np.pi * 0.37 * T)) == pytest.approx(0.37, rel=1e-3)


def test_a_continuums_detail_holds_no_numbers():
    """The report counts complex runs by their detail (reproduce.measures.details): a detail
    with lambda_max or K in it made every run a kind of its own."""
    a = classify(T, window(QUASI), lyap=LyapunovEstimate(1e-5, 2e-5, 5e4, 20))
    b = classify(T, window(QUASI), lyap=LyapunovEstimate(-3e-5, 4e-5, 5e4, 20))
    assert a.attractor == b.attractor == "undetermined" and a.detail == b.detail
