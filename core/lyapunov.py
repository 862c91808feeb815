"""lambda_max from the tangent-linear log-growths the kernels record.

The kernels renormalise the tangent every T_r time units and store log|e| before each
renormalisation; lambda_max is their time average. We discard a transient, split the
rest into blocks and report the mean with the standard error of the block means,
sigma = sd(block means) / sqrt(blocks): the paper's 0.0008(9) means 0.0008 +- 0.0009.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: Fraction of the run discarded before measuring (the tangent aligns with the leading
#: direction and the state settles on its attractor). Half the run: at t_end = 1e5 that
#: leaves 5e4 time units, over ~100 times the slowest decay time we measured off the
#: Hopf curve.
TRANSIENT_FRACTION = 0.5
#: Number of blocks for the standard error.
N_BLOCKS = 20


@dataclass(frozen=True, slots=True)
class LyapunovEstimate:
    """lambda_max (1 / model time unit) with its standard error, over ``t_measured``."""

    value: float
    error: float
    t_measured: float
    n_blocks: int

    def format(self) -> str:
        """The paper's notation, e.g. 0.0008(9) for 0.0008 +- 0.0009."""
        return format_with_error(self.value, self.error)


def estimate(logs: np.ndarray, interval: float, transient_fraction: float = TRANSIENT_FRACTION,
             n_blocks: int = N_BLOCKS) -> LyapunovEstimate:
    """Block-average the per-renormalisation log-growths ``logs`` (one per ``interval``)."""
    logs = np.asarray(logs, dtype=float)
    start = int(len(logs) * transient_fraction)
    tail = logs[start:]
    if len(tail) == 0:
        return LyapunovEstimate(math.nan, math.nan, 0.0, 0)
    value = float(tail.sum() / (len(tail) * interval))
    nb = min(n_blocks, len(tail))
    if nb < 2:
        return LyapunovEstimate(value, math.nan, len(tail) * interval, nb)
    blocks = np.array_split(tail, nb)
    means = np.array([b.sum() / (len(b) * interval) for b in blocks])
    error = float(means.std(ddof=1) / math.sqrt(nb))
    return LyapunovEstimate(value, error, len(tail) * interval, nb)


def running(logs: np.ndarray, interval: float, points: int = 1000) -> tuple[np.ndarray, np.ndarray]:
    """The running estimate lambda(t) = sum of log-growths up to t / t, from t = 0.

    This is the convergence curve of the paper's Fig. 3J-L, decimated to ``points``.
    """
    logs = np.asarray(logs, dtype=float)
    if len(logs) == 0:
        return np.zeros(0), np.zeros(0)
    t = interval * np.arange(1, len(logs) + 1)
    lam = np.cumsum(logs) / t
    step = max(1, len(logs) // points)
    return t[step - 1::step], lam[step - 1::step]


def format_with_error(value: float, error: float) -> str:
    """Format value(error) with the error's leading digit, as in 0.0008(9) or -0.15(6)."""
    if not math.isfinite(value):
        return "nan"
    if not math.isfinite(error) or error <= 0.0:
        return f"{value:.4g}"
    decimals = max(0, -math.floor(math.log10(error)))
    if value != 0.0:  # an error far below the value: show 6 significant digits, not 20
        decimals = min(decimals, max(0, 5 - math.floor(math.log10(abs(value)))))
    digit = round(error * 10**decimals)
    if digit == 10:  # 0.0095 rounds up to one more significant place
        decimals -= 1
        digit = 1
    if decimals == 0:
        return f"{value:.0f}({digit})"
    return f"{value:.{decimals}f}({digit})"
