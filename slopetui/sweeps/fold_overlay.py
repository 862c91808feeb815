"""The fold-of-cycles curve over a sweep's (k, tau), (a, tau), (b, tau) or (c, tau) plane,
for the faces to draw beside the exact Hopf curve (``render_sweep(fold=...)``).

The curve is continued (core.fold_continuation): the fold of the branch from the Hopf point
at the top tau of the sweep's axis, followed as a curve down to its bottom tau, or to the
Bautin point where it ends on the Hopf curve (below it the Hopf point is supercritical and
no band of bistability exists). At the defaults that is 6.4 s CPU from tau = 10 to 2 for 33
points, where the fold found tau by tau (core.fold_curve, one branch from the Hopf point
each) takes 0.8 s a tau (benchmarks/bench_fold_curve.py); a face still computes it on
request, never on a redraw. Where the curve
cannot start (no subcritical fold at the top tau) the fold is looked for tau by tau, as
before. Planes with tau across (x) are not drawn: the sweeps and the paper put tau up the
y axis.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import TYPE_CHECKING

import numpy as np

from slopetui.sweeps.spec import SweepSpec

if TYPE_CHECKING:  # core.fold_curve loads scipy: imported where the curve is computed
    from core.fold_curve import FoldPoint

Curve = tuple[np.ndarray, np.ndarray]


#: The x parameters of the planes (x, tau) the fold curve is drawn in.
FOLD_PARAMS = ("k", "a", "b", "c")


def has_fold_plane(spec: SweepSpec) -> bool:
    """Is the sweep an (x, tau) phase diagram with x in FOLD_PARAMS, a plane the fold
    curve is drawn in?"""
    return spec.y is not None and spec.y.param == "tau" and spec.x.param in FOLD_PARAMS


def inside(spec: SweepSpec, x: np.ndarray, tau: np.ndarray) -> Curve:
    """The curve's points inside the sweep's plane (a point outside would stretch the
    axes: the report's table goes on to tau = 60)."""
    assert spec.y is not None
    xs, ys = spec.x.values(), spec.y.values()
    keep = (x >= min(xs)) & (x <= max(xs)) & (tau >= min(ys)) & (tau <= max(ys))
    return x[keep], tau[keep]


def fold_overlay(spec: SweepSpec, progress: Callable[[float, float | None], None] | None = None
                 ) -> Curve | None:
    """The fold of cycles at each tau of the sweep's axis, at its fixed parameters, as
    (x, tau) arrays inside its plane; None for a sweep that is not such a plane (see
    has_fold_plane). ``progress(tau, fold)`` is called after each tau (fold None: no fold
    there, e.g. a supercritical Hopf point)."""
    if not has_fold_plane(spec):
        return None
    assert spec.y is not None
    taus = [float(t) for t in spec.y.values()]
    continued = _continued(spec, max(taus), min(taus), progress)
    if continued is not None:
        return inside(spec, *continued)
    points = []
    from core.fold_curve import fold_curve  # numba and scipy: see the TYPE_CHECKING import

    for point in fold_curve(spec.base, taus, name=spec.x.param):
        if progress is not None:
            progress(point.second, point.fold)
        points.append(point)
    return inside(spec, *curve_of(points))


#: The most points of the continued curve (tau = 10 to 2 takes 33 at the defaults).
CURVE_POINTS = 400


def _continued(spec: SweepSpec, top: float, bottom: float,
               progress: Callable[[float, float | None], None] | None) -> Curve | None:
    """The continued fold curve from tau = top down to bottom (or its Bautin end), as
    (x, tau) arrays; None where it cannot start (no subcritical fold at the top)."""
    from core.fold_continuation import walk
    from core.fold_start import start_at_fold
    from core.lyapunov_coefficient import first_lyapunov
    from core.orbit import OrbitError

    name = spec.x.param
    base = spec.base.with_(tau=top)
    try:
        if first_lyapunov(base, name).l1 < 0 or top == bottom:
            return None  # supercritical at the top: the fold there bounds no bistable band
        curve = start_at_fold(base, (name, "tau"), bottom)
        xs, ts = [], []
        for point in walk(curve, bottom, CURVE_POINTS):
            if progress is not None:
                progress(point.second, point.first)
            xs.append(point.first)
            ts.append(point.second)
    except (OrbitError, ValueError):
        return None
    return np.array(xs), np.array(ts)


def curve_of(points: Iterable[FoldPoint]) -> Curve:
    """The (x, tau) arrays of the points that have a fold (core.fold_curve's points, the
    second parameter being tau)."""
    found = [(p.fold, p.second) for p in points if p.fold is not None]
    return np.array([k for k, _ in found]), np.array([t for _, t in found])
