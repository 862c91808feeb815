"""The exact Hopf curve of the sliding state, in the coordinates of a phase-diagram plane.

Only planes with tau on one axis have the curve: (k, tau) from core.stability's k_H(tau),
and (a, tau), (b, tau), (c, tau) from its friction-plane curves. Either axis order works.

Plane geometry over a sweep's axes, no drawing (slopetui.plots draws the curve it gets).
It lives here rather than in core/: core's source digest keys the result cache and
numba's cache, and a sampling density chosen for the screen must not invalidate either.
"""

from __future__ import annotations

import math

import numpy as np

from core.params import Params
from core.stability import hopf_curve_friction, hopf_curve_k_tau, hopf_tau

#: The friction parameters whose (name, tau) plane has a Hopf curve.
FRICTION_PARAMS: tuple[str, ...] = ("a", "b", "c")
#: Samples of the curve: a few hundred resolve it well beyond a terminal's cells.
N_SAMPLES = 400
#: Samples of the friction curves, which spread over all tau > pi / sqrt(2k) and so
#: land partly outside any plotted range.
N_FRICTION_SAMPLES = 1600

Curve = tuple[np.ndarray, np.ndarray]


def hopf_boundary(base: Params, x_param: str, y_param: str,
                  x_range: tuple[float, float], y_range: tuple[float, float]) -> Curve | None:
    """The exact Hopf curve in the plane (x_param, y_param), as (x values, y values).

    Coordinates are parameter values (model units), ordered along the curve, keeping only
    the points inside x_range and y_range (either bound order). The parameters not on the
    axes come from ``base``. Returns empty arrays when the curve misses the ranges, and None
    when the plane has no curve: neither axis is tau, the other axis is d, v or delta, or
    the curve is undefined (F'(v) <= 0 for (k, tau), k <= 0 for the friction planes).
    """
    if y_param == "tau":
        other, other_range, tau_range, swapped = x_param, x_range, y_range, False
    elif x_param == "tau":
        other, other_range, tau_range, swapped = y_param, y_range, x_range, True
    else:
        return None
    try:
        if other == "k":
            values, taus = _k_tau_curve(base, _ordered(other_range), _ordered(tau_range))
        elif other in FRICTION_PARAMS:
            values, taus = _friction_curve(base, other)
        else:
            return None
    except ValueError:
        # core.stability's own check: the sliding state has no Hopf branch here
        return None
    values, taus = _clip(values, taus, _ordered(other_range), _ordered(tau_range))
    return (taus, values) if swapped else (values, taus)


def _ordered(bounds: tuple[float, float]) -> tuple[float, float]:
    lo, hi = sorted(float(b) for b in bounds)
    return lo, hi


def _k_tau_curve(base: Params, k_range: tuple[float, float],
                 tau_range: tuple[float, float]) -> Curve:
    """k_H over the taus where it can fall inside k_range (k_H falls monotonically with tau).

    Sampling only that stretch of tau keeps the whole sample on screen, however steep the
    curve (k_H ~ pi^2 / (2 tau^2) at small tau).
    """
    f1 = base.F1
    if f1 <= 0.0:
        # an empty tau sample would skip core's own check, so test F'(v) > 0 here too
        raise ValueError("the Hopf curve in k needs F'(v) > 0")
    tau_lo, tau_hi = max(tau_range[0], 0.0), tau_range[1]
    k_lo, k_hi = k_range
    k_min = 0.5 * f1 * f1                # k_H -> F'^2 / 2 as tau -> inf
    if k_hi <= k_min or tau_hi <= 0.0:
        return np.zeros(0), np.zeros(0)
    tau_lo = max(tau_lo, _tau_at_k(k_hi, f1))
    if k_lo > k_min:
        tau_hi = min(tau_hi, _tau_at_k(k_lo, f1))
    if tau_lo > tau_hi:
        return np.zeros(0), np.zeros(0)
    taus = _dense_samples(tau_lo, tau_hi, N_SAMPLES)
    return hopf_curve_k_tau(base, taus), taus


def _tau_at_k(k: float, f1: float) -> float:
    """tau_H where k_H = k > F'^2 / 2: the inverse of k_H(tau), through omega."""
    return hopf_tau(math.sqrt(2.0 * k - f1 * f1), f1, k)


def _dense_samples(lo: float, hi: float, n: int) -> np.ndarray:
    """n linear and n geometric samples of [lo, hi] (lo > 0), merged: even on linear axes,
    and still dense near lo on log axes."""
    if lo <= 0.0:
        lo = hi * 1e-6
    return np.unique(np.concatenate((np.linspace(lo, hi, n), np.geomspace(lo, hi, n))))


def _friction_curve(base: Params, name: str) -> Curve:
    # v = 0 divides by zero for a and b: those points come out non-finite and are clipped
    with np.errstate(divide="ignore", invalid="ignore"):
        return hopf_curve_friction(base, name, N_FRICTION_SAMPLES)


def _clip(values: np.ndarray, taus: np.ndarray, value_range: tuple[float, float],
          tau_range: tuple[float, float]) -> Curve:
    """Keep the finite points inside both ranges, in their order along the curve.

    The kept points are one stretch of the curve: both curves are graphs over tau
    (one k or friction value per tau) and monotone, so they cross the box only once.
    Points within round-off of a bound count as inside: the (k, tau) sample starts
    exactly where the curve enters the window, and k_H(tau) recomputed there may
    overshoot the bound in the last digit.
    """
    values, taus = np.asarray(values, dtype=float), np.asarray(taus, dtype=float)
    keep = (np.isfinite(values) & np.isfinite(taus)
            & _within(values, value_range) & _within(taus, tau_range))
    return np.clip(values[keep], *value_range), np.clip(taus[keep], *tau_range)


def _within(x: np.ndarray, bounds: tuple[float, float], rel: float = 1e-9) -> np.ndarray:
    lo, hi = bounds
    slack = rel * max(abs(lo), abs(hi), hi - lo)
    return (x >= lo - slack) & (x <= hi + slack)
