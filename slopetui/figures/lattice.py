"""The cells of a phase diagram: edges around a sweep axis's values.

Each lattice point is the centre of its cell. Between two points the edge is their
midpoint, arithmetic on a linear axis and geometric (the midpoint in log space) on a log
axis, so that on the log axis the figure is drawn on every cell is centred on its point.
The outer edges lie half a step beyond the end points, the same step as the neighbour's.
"""

from __future__ import annotations

import numpy as np

#: A single-point axis has no step: its cell spans this fraction of |value| on either
#: side (or +-0.5 around 0) on a linear axis, and this factor either way on a log axis.
SINGLE_HALF_WIDTH = 0.05
SINGLE_LOG_FACTOR = 1.1


def cell_edges(values: np.ndarray, log: bool) -> np.ndarray:
    """n + 1 edges around n axis values (ascending or descending, as the values go).

    Raises ValueError for no values, non-finite ones, or a value <= 0 on a log axis.
    """
    v = np.asarray(values, dtype=float)
    if v.size == 0:
        raise ValueError("an axis without values has no cells")
    if not np.all(np.isfinite(v)):
        raise ValueError("axis values must be finite")
    if log:
        if np.any(v <= 0.0):
            raise ValueError("a log axis needs values > 0")
        if v.size == 1:
            return np.array([v[0] / SINGLE_LOG_FACTOR, v[0] * SINGLE_LOG_FACTOR])
        return np.exp(_linear_edges(np.log(v)))
    if v.size == 1:
        half = SINGLE_HALF_WIDTH * abs(v[0]) or 0.5
        return np.array([v[0] - half, v[0] + half])
    return _linear_edges(v)


def _linear_edges(v: np.ndarray) -> np.ndarray:
    mid = 0.5 * (v[:-1] + v[1:])
    first = v[0] - (mid[0] - v[0])
    last = v[-1] + (v[-1] - mid[-1])
    return np.concatenate([[first], mid, [last]])
