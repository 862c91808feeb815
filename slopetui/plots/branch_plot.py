"""The bifurcation diagram of a continuation (core.continuation): each periodic orbit of
the branch as a point, amplitude (peak to peak of m_y) against the parameter continued
in, stable and unstable orbits apart, and the bifurcations located on the branch marked
where they are.

A branch may fold back (a fold of cycles turns it), so it is not a function of the
parameter: it is drawn as points, never joined, so that no line crosses between its
two sheets. Stable orbits are 'o' in green and unstable ones '.' in red (the usual thick
and dashed lines of a bifurcation diagram); each bifurcation type has a capital letter of
its own, so the diagram reads with colour off.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

import numpy as np

from slopetui.plots.canvas import LegendEntry, Series, axis_label, message_block, note, render

Y_LABEL = "m_y amplitude (peak to peak)"


@dataclass(frozen=True, slots=True)
class BranchStyle:
    """How one kind of mark is drawn: plotext colour, one-character marker, legend name."""

    color: str
    marker: str
    label: str


STABLE = BranchStyle("green", "o", "stable")
UNSTABLE = BranchStyle("red", ".", "unstable")
#: By bifurcation type (core.continuation.Bifurcation.type), in legend order. Letters,
#: not symbols: they name the type with colour off too.
BIFURCATION_STYLES: Mapping[str, BranchStyle] = MappingProxyType({
    "fold": BranchStyle("orange", "F", "fold"),
    "period-doubling": BranchStyle("magenta", "D", "period-doubling"),
    "torus": BranchStyle("cyan", "T", "torus"),
    "branch-point": BranchStyle("default", "B", "branch-point"),
    "hopf": BranchStyle("default", "H", "hopf"),
})
#: A type this module does not know yet: still drawn and counted, never dropped.
OTHER = BranchStyle("default", "?", "other")


def render_branch(param: str, points: Sequence[Mapping[str, Any]],
                  bifurcations: Sequence[Mapping[str, Any]], *, title: str = "",
                  width: int = 80, height: int = 24, color: bool = True) -> str:
    """The branch's ``points`` (records with ``value``, the parameter in model units,
    ``amplitude``, peak to peak of m_y, ``period`` and ``stable``, in branch order) and
    its ``bifurcations`` (records with ``type``, ``value`` and ``period``), each marked at
    its parameter value with the amplitude interpolated along the branch.

    The legend counts stable and unstable orbits and each bifurcation type. Points with a
    non-finite value or amplitude are left out and counted. Returns exactly ``height``
    lines of at most ``width`` columns (a message block when there is no point to draw);
    with ``color`` False, no ANSI escapes. Raises ValueError for a size too small.
    """
    values, amplitudes, periods, stable = _arrays(points)
    shown = np.isfinite(values) & np.isfinite(amplitudes)
    if not shown.any():
        what = f"{len(points)} points, none plottable" if len(points) else "no points yet"
        prefix = f"{title}: " if title else ""
        return message_block(f"{prefix}{what} on this branch in {param}.", width, height)
    series: list[Series] = []
    legend: list[LegendEntry] = []
    for style, mask in ((STABLE, shown & stable), (UNSTABLE, shown & ~stable)):
        if mask.any():
            series.append(Series(values[mask], amplitudes[mask], style.marker, style.color))
            legend.append(LegendEntry(style.marker, style.color,
                                      f"{style.label} {int(mask.sum())}"))
    marks = _bifurcation_marks(bifurcations, values[shown], amplitudes[shown],
                               periods[shown])
    series.extend(marks.values())  # last: a bifurcation is drawn over the orbits near it
    counts = Counter(str(b["type"]) for b in bifurcations)
    for kind, n in counts.items():
        style = bifurcation_style(kind)
        legend.append(LegendEntry(style.marker, style.color, f"{kind} {n}"))
    hidden = len(points) - int(shown.sum())
    if hidden:
        legend.append(note(f"{hidden} not shown (not finite)"))
    xs = np.concatenate([s.xs for s in series])
    return render(series, legend, x_label=axis_label(param), y_label=Y_LABEL, x_log=False,
                  y_log=False, title=title, width=width, height=height, color=color,
                  x_range=(float(xs.min()), float(xs.max())))


def bifurcation_style(kind: str) -> BranchStyle:
    """Marker and colour of a bifurcation type (OTHER for a type not listed)."""
    return BIFURCATION_STYLES.get(kind, OTHER)


def _arrays(points: Sequence[Mapping[str, Any]]
            ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(values, amplitudes, periods, stable) of the points, as arrays in branch order."""
    def column(key: str) -> np.ndarray:
        return np.array([_number(p.get(key)) for p in points], dtype=float)

    return (column("value"), column("amplitude"), column("period"),
            np.array([bool(p.get("stable")) for p in points], dtype=bool))


def _number(x: Any) -> float:
    """A stored number as a float; None (a missing column) is NaN."""
    return math.nan if x is None else float(x)


def _bifurcation_marks(bifurcations: Sequence[Mapping[str, Any]], values: np.ndarray,
                       amplitudes: np.ndarray, periods: np.ndarray) -> dict[str, Series]:
    """One series per bifurcation type, each mark at (its value, the branch's amplitude
    there); a bifurcation with no finite value is counted in the legend, not drawn."""
    xs: dict[str, list[float]] = {}
    ys: dict[str, list[float]] = {}
    for bif in bifurcations:
        kind, value = str(bif["type"]), _number(bif.get("value"))
        if not math.isfinite(value):
            continue
        amplitude = (0.0 if kind == "hopf"  # the orbit is born there with zero amplitude
                     else amplitude_at(value, _number(bif.get("period")), values, amplitudes,
                                       periods))
        xs.setdefault(kind, []).append(value)
        ys.setdefault(kind, []).append(amplitude)
    return {kind: Series(np.array(xs[kind]), np.array(ys[kind]), bifurcation_style(kind).marker,
                         bifurcation_style(kind).color) for kind in xs}


def amplitude_at(value: float, period: float, values: np.ndarray, amplitudes: np.ndarray,
                 periods: np.ndarray) -> float:
    """The branch's amplitude at parameter ``value``, interpolated linearly between two
    neighbouring points (in branch order).

    A folding branch passes a value more than once: of the segments near ``value`` the
    one whose interpolated period is nearest ``period`` (the bifurcation's, model time)
    is taken. A fold lies at the branch's turning point, which the neighbouring points
    may all miss on one side: the parameter is then clipped to the nearest segment's end.
    """
    if len(values) == 1:
        return float(amplitudes[0])
    v0, v1 = values[:-1], values[1:]
    span = v1 - v0
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(span != 0, (value - v0) / span, 0.5)
    t = np.clip(t, 0.0, 1.0)
    # distances in units of the branch's own ranges, so the two terms are comparable
    v_scale = max(float(np.ptp(values)), 1e-12)
    miss = np.abs(v0 + t * span - value) / v_scale
    p_at = periods[:-1] + t * (periods[1:] - periods[:-1])
    if math.isfinite(period) and np.isfinite(p_at).all():
        miss = miss + np.abs(p_at - period) / max(float(np.ptp(periods)), 1e-12)
    i = int(np.argmin(miss))
    return float(amplitudes[i] + t[i] * (amplitudes[i + 1] - amplitudes[i]))
