"""The return time is the minimal one: a flat maximum's timing noise is not a longer period.

At large b the maxima of m_y are flat-topped, and their times, refined between samples,
scatter with the sampling phase: at b = 18, k = 12, tau = 10 (Euler, dt 1e-3, window
sampled every 0.01) the spacings of successive maxima were 11.08557-11.08622 in a
pattern that repeats every few maxima, the heights equal to 2e-8 of the amplitude. The
old rule counted spacing defects above 1e-5 of the period as a real alternation and
called such orbits period-2, -3 or -4."""

from __future__ import annotations

import numpy as np

from core.returns import find_return

STEP = 0.01          # the window's sample step
PERIOD = 11.0859     # b = 18, k = 12, tau = 10: the orbit's period
AMPLITUDE = 7.2439


def flat_topped_maxima(n: int = 90) -> tuple[np.ndarray, np.ndarray]:
    """Maxima as the window at b = 18, k = 12, tau = 10 shows them: one a period, their
    times off by up to 0.038 of a sample in a pattern of four (the sampling phase's), their
    heights equal to 2e-8 of the amplitude."""
    jitter = np.array([0.0, 3.4e-4, -2.9e-4, 2.5e-4])   # measured scatter, time units
    wobble = np.array([0.0, 9e-8, 1.3e-7, 5e-8])        # measured scatter of the heights
    i = np.arange(n)
    return PERIOD * i + jitter[i % 4], 5.39688581 + wobble[i % 4]


def test_flat_maxima_with_sampling_jitter_return_after_one_maximum():
    t, y = flat_topped_maxima()
    ret = find_return(t, y, AMPLITUDE, basic_period=11.4599, step=STEP)
    assert ret is not None
    assert (ret.maxima, ret.count) == (1, 1)
    assert abs(ret.time - PERIOD) < 1e-4   # the mean of the jitter


def test_a_real_alternation_of_the_spacing_is_still_seen():
    # two maxima a period of nearly equal height but spaced 2.86 and 7.51 (tau = 10, k = 20):
    # far beyond a sample's timing noise
    i = np.arange(80)
    t = 10.37 * (i // 2) + np.where(i % 2, 2.86, 0.0)
    y = 2.2128 + 5e-4 * (i % 2)
    ret = find_return(t, y, 2.5, basic_period=10.5, step=STEP)
    assert ret is not None and ret.maxima == 2 and ret.count == 1


def test_a_plateau_s_round_off_ripple_is_not_a_row_of_maxima():
    # the stick phase of a square wave (k = 7, tau = 60): m_y flat at -0.59 to round-off,
    # its local maxima 2e-16 A apart; one slip a period
    from core.classify import classify
    from core.params import Params

    t = np.arange(0.0, 1000.0, 0.01)
    slip = np.sin(2 * np.pi * t / 60.6)
    y = -0.59 + 2.48 * np.maximum(slip, 0.0) ** 3
    y = y + np.where(slip <= 0.0, 1e-16 * np.sin(2 * np.pi * t / 0.37), 0.0)
    w = np.zeros((5, len(t)))
    w[1] = y
    s = classify(t, w, p=Params(k=7, tau=60))
    assert (s.regime, s.maxima_per_period) == ("oscillatory", 1), s.detail
