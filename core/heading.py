"""Where a run that still sits at an unstable rest state is headed.

A window at rest whose rest state linear theory calls unstable (core.rest_stability) has
not departed yet: near the Hopf curve the leading root is tiny (+1.8e-7 at k = 6,
tau = 60 with the default noise) and a window started from delta = 1e-6 sits there for
~1e8 time units. Its label is where it goes, when that can be decided: the branch of
periodic orbits born at the Hopf point in k (core.continuation.Branch.from_hopf) is
followed until it reaches the run's k. If the orbit there is stable, the run is headed
for it: *oscillatory*. Past a subcritical Hopf point the branch first runs back to the
fold of cycles and returns as the large cycle; past a supercritical one its small
orbits are stable at once. Otherwise (the branch ends first, or its orbit at k is not
stable, or the Hopf point cannot be found) the regime is *undetermined*, with the reason.
This is one attractor found, not a proof that no other exists.

**Cost.** A branch walk is expensive (tau = 60: 46 points to k = 6, ~17 s on a loaded
core at the grid below; tau = 10: ~4 s), and is only needed for the rare run whose
window sits at an unstable rest state. One walk serves every k at the same other
parameters: each process keeps the last few (``_WALKS``), extended on demand.
"""

from __future__ import annotations

import math
from collections import OrderedDict
from dataclasses import dataclass

from core.continuation import Branch, BranchPoint, criticality
from core.fold_curve import step_sizes
from core.orbit import OrbitError
from core.params import ParameterError, Params

#: The delay grid of the branch: N points per delay (RK4). The regime needs the orbit's
#: stability, not its digits: at tau = 60 (dt = 0.1) the branch reached k = 6.1254 with
#: peak-to-peak 2.411 and period 60.661, at dt = 0.01 k = 6.1275, 2.411, 60.661, both
#: stable, for 17 s against 100 s.
POINTS_PER_DELAY = 600
#: ... and the step at most this: beyond tau = 60 the delay grows, the slips do not.
MAX_DT = 0.1
#: Branch points a walk may take before it gives up (tau = 60 reaches k = 6 in 46).
MAX_POINTS = 200
#: The largest delay a walk is tried at. Measured on a loaded core: tau = 0.5: 1 s,
#: tau = 2: 11 s, tau = 10: 4-11 s, tau = 60: 17-25 s for 46 points; at tau = 100 (dt 0.1,
#: N = 1000) the first branch point came after 177 s and each next one took ~160 s (mostly
#: in GMRES): the fold lies ~25 points away. Beyond this the regime is undetermined, saying so; a bound in points,
#: not in wall time, so that a label does not depend on the machine.
MAX_TAU = 60.0
#: Walks kept per process (one per (a, b, c, d, v, tau)).
KEPT_WALKS = 8


@dataclass(frozen=True, slots=True)
class Heading:
    """Where the run is headed: ``regime`` (oscillatory or undetermined) and why."""

    regime: str
    reason: str


@dataclass
class _Walk:
    branch: Branch
    hopf_k: float
    end: str = ""   # why the walk stopped, once it has


_WALKS: OrderedDict[tuple[float, ...], _Walk] = OrderedDict()


def heading(p: Params) -> Heading:
    """Where a run at the unstable rest state of p goes (see the module docstring)."""
    if p.tau > MAX_TAU:
        return Heading("undetermined", f"no Hopf branch followed beyond tau = {MAX_TAU:g} (too "
                                       "costly for one run)")
    if p.F1 <= 0.0:
        return Heading("undetermined", f"F'(v) = {p.F1:.4g} <= 0: the rest state is unstable "
                                       "for every k, no Hopf branch to follow")
    try:
        walk = _walk(p)
    except (OrbitError, ParameterError, ArithmeticError, ValueError) as exc:
        return Heading("undetermined", f"no Hopf branch to follow: {exc}")
    bracket = _reach(walk, p.k)
    if bracket is None:
        return Heading("undetermined", f"the Hopf branch from k = {walk.hopf_k:.6g} did not reach "
                                       f"k = {p.k:g}: {walk.end}")
    a, b = bracket
    kind = criticality(walk.branch.points)
    if a.stable and b.stable:
        s = (p.k - a.value) / (b.value - a.value) if b.value != a.value else 0.0
        period = a.period + s * (b.period - a.period)
        amp = a.amplitude + s * (b.amplitude - a.amplitude)
        return Heading("oscillatory", f"headed for the stable cycle of the {kind} Hopf point at "
                                      f"k = {walk.hopf_k:.6g} (period {period:.4g}, peak-to-peak "
                                      f"{amp:.3g} at k = {p.k:g})")
    why = "unstable" if not (a.stable or b.stable) else "changes stability"
    return Heading("undetermined", f"the cycle of the {kind} Hopf point at k = {walk.hopf_k:.6g} "
                                   f"is {why} at k = {p.k:g}: the destination is not known")


def _key(p: Params) -> tuple[float, ...]:
    return (p.a, p.b, p.c, p.d, p.v, p.tau)


def _walk(p: Params) -> _Walk:
    """The walk for p's parameters other than k and delta, started if not kept."""
    key = _key(p)
    if key in _WALKS:
        _WALKS.move_to_end(key)
        return _WALKS[key]
    first, largest = step_sizes(p, "k")
    dt = min(MAX_DT, p.tau / POINTS_PER_DELAY)
    branch, hopf = Branch.from_hopf(p, "k", dt, 1e-3, first, largest)
    branch.first()
    walk = _Walk(branch, hopf.value)
    _WALKS[key] = walk
    while len(_WALKS) > KEPT_WALKS:
        _WALKS.popitem(last=False)
    return walk


def _reach(walk: _Walk, k: float) -> tuple[BranchPoint, BranchPoint] | None:
    """The first two consecutive branch points that bracket k while k grows, walking
    further as needed; None when the walk ends first."""
    pts = walk.branch.points
    if len(pts) > 1 and pts[0].value >= k and pts[1].value > pts[0].value:
        return pts[0], pts[1]  # a supercritical branch that starts just past this k
    i = 1
    while True:
        while i < len(pts):
            a, b = pts[i - 1], pts[i]
            if a.value <= k <= b.value:
                return a, b
            i += 1
        if walk.end:
            return None
        if len(pts) >= MAX_POINTS:
            walk.end = f"{MAX_POINTS} branch points computed"
            return None
        try:
            walk.branch.advance(1e-9)
        except OrbitError as exc:
            walk.end = str(exc)
            return None
        if not math.isfinite(pts[-1].value):
            walk.end = "the branch left the finite range"
            return None
