"""Axis ticks of the terminal plots at round numbers, as many as the plot's size holds.

plotext 5 puts its ticks at equal fractions of the data's range and prints each with
as many digits as tell them apart: 5.474, 8.947 on an axis from 2 to 12, "-0.0000000"
where a tick lands a rounding error below zero, and 0.1, 0.7, 4.5, 29.9 on a log axis.
Here the ticks are steps of 1, 2 or 5 times a power of ten (on a log axis: powers of ten,
with 2 and 5 times them when the axis spans less than two decades), chosen from the
axis' range and the room the plot gives them, and written with the decimals the step
needs; zero is "0", never "-0".

The range is plotext's own (its ``get_lim``: the data's minimum and maximum; a constant
m as 0.5 m to 1.5 m, zero as -1 to 1; on a log axis the same on log10 of the data), or
the range the caller pinned; the ticks fall inside it.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence

import numpy as np

#: Columns between the starts of two x tick labels, at least: the widest label and two
#: spaces (plotext drops a label that would touch its neighbour, check_space).
X_LABEL_GAP = 2
#: Rows between two y ticks, at least: with fewer the labels read as one column of
#: numbers rather than marks on an axis (plotext's own default is about one in three).
Y_TICK_ROWS = 2
#: The 1-2-5 steps, per decade.
MANTISSAS = (1, 2, 5)
#: Plain decimals up to this many (0.000001); beyond, or from 1e6 up, the e notation.
MAX_DECIMALS = 6
MAX_PLAIN = 1e6


def data_range(values: Sequence[float] | np.ndarray, log: bool = False) -> tuple[float, float]:
    """The axis range plotext gives these values (module docstring), in data units;
    (-1, 1) without any (on a log axis: 0.1 to 10)."""
    arr = np.asarray(values, dtype=float).ravel()
    arr = arr[np.isfinite(arr) & ((arr > 0) if log else True)]
    lo, hi = (float(arr.min()), float(arr.max())) if len(arr) else (0.0, 0.0)
    if log and len(arr):
        lo, hi = math.log10(lo), math.log10(hi)
    if lo == hi:
        lo, hi = (0.5 * lo, 1.5 * lo) if lo != 0 else (-1.0, 1.0)
        lo, hi = min(lo, hi), max(lo, hi)
    return (10.0 ** lo, 10.0 ** hi) if log else (lo, hi)


def _decimals(step: float) -> int:
    return max(0, -math.floor(math.log10(step) + 1e-9))


def tick_label(value: float, step: float) -> str:
    """``value`` (a multiple of ``step``) with the decimals ``step`` needs: 0.25 at a step
    of 0.05, 150 at 50; the e notation for very small steps and very large values; zero
    with the others' decimals ("0.0") and never with a minus sign."""
    decimals = _decimals(step)
    plain = decimals <= MAX_DECIMALS and abs(value) < MAX_PLAIN
    if value == 0 or abs(value) < step * 1e-6:
        return f"{0.0:.{decimals}f}" if plain else "0"
    if plain:
        text = f"{value:.{decimals}f}"
    else:
        digits = max(1, math.floor(math.log10(abs(value))) - math.floor(math.log10(step) + 1e-9) + 1)
        text = _short_e(f"{value:.{digits - 1}e}")
    return text


def _short_e(text: str) -> str:
    """1.5e-07 as 1.5e-7, 2e+06 as 2e6."""
    mantissa, _, exponent = text.partition("e")
    return f"{mantissa}e{int(exponent)}"


def linear_ticks(lo: float, hi: float, max_count: int) -> tuple[list[float], float]:
    """The multiples of the smallest 1-2-5 step that leave at most ``max_count`` (>= 2)
    of them in [lo, hi], and the step."""
    span = hi - lo
    if not (math.isfinite(span) and span > 0):
        return [lo], 1.0
    exponent = math.floor(math.log10(span / max(max_count, 2)))
    while True:
        for mantissa in MANTISSAS:
            step = mantissa * 10.0 ** exponent
            first, last = math.ceil(lo / step - 1e-9), math.floor(hi / step + 1e-9)
            if last - first + 1 <= max(max_count, 2):
                return [k * step if k else 0.0 for k in range(first, last + 1)], step
        exponent += 1


def log_ticks(lo: float, hi: float, max_count: int) -> list[float]:
    """Powers of ten in [lo, hi] (every second, fifth... when too many), with 2 and 5
    times them when they fit and the range spans less than two decades; [] when fewer
    than two such values fall in the range (the caller uses linear ticks)."""
    if not (0 < lo < hi):
        return []
    first, last = math.ceil(math.log10(lo) - 1e-9), math.floor(math.log10(hi) + 1e-9)
    if last - first < 2:
        ticks = [m * 10.0 ** e for e in range(first - 1, last + 1) for m in MANTISSAS]
        ticks = [t for t in ticks if lo * (1 - 1e-9) <= t <= hi * (1 + 1e-9)]
        if 2 <= len(ticks) <= max_count:
            return ticks
    decades = list(range(first, last + 1))
    every = max(1, math.ceil(len(decades) / max(max_count, 2)))
    ticks = [10.0 ** e for e in decades if (e - first) % every == 0]
    return ticks if len(ticks) >= 2 else []


def log_label(value: float) -> str:
    """A tick of a log axis: 0.01, 0.5, 20, 1e6, 1e-7."""
    if 1e-4 <= value < MAX_PLAIN:
        return f"{value:g}"
    return _short_e(f"{value:.0e}")


def axis_ticks(lo: float, hi: float, *, log: bool, length: int, label_room: bool
               ) -> tuple[list[float], list[str]]:
    """Ticks and their labels for an axis over [lo, hi] (data units) ``length`` cells
    long: columns of an x axis (``label_room``: each label needs its width and
    X_LABEL_GAP), rows of a y axis (a tick every Y_TICK_ROWS at most)."""
    count = max(2, length // Y_TICK_ROWS) if not label_room else max(2, length // 4)
    while True:
        if log:
            ticks = log_ticks(lo, hi, count)
            if ticks:
                labels = [log_label(t) for t in ticks]
                if not label_room or _fits(ticks, labels, lo, hi, length, log=True) or count <= 2:
                    return ticks, labels
                count -= 1
                continue
        ticks, step = linear_ticks(lo, hi, count)
        labels = [tick_label(t, step) for t in ticks]
        if not label_room or _fits(ticks, labels, lo, hi, length, log=log) or count <= 2:
            return ticks, labels
        count -= 1


def _fits(ticks: Sequence[float], labels: Sequence[str], lo: float, hi: float, length: int,
          *, log: bool) -> bool:
    """Whether neighbouring x labels are at least their width and X_LABEL_GAP apart."""
    def column(v: float) -> float:
        if log:
            return length * (math.log10(v) - math.log10(lo)) / (math.log10(hi) - math.log10(lo))
        return length * (v - lo) / (hi - lo)

    width = max(map(len, labels), default=0) + X_LABEL_GAP
    cols = [column(t) for t in ticks]
    return all(b - a >= width for a, b in itertools.pairwise(cols))
