"""The first real crossing of a kind on a one-parameter branch: where a period-doubling or
a torus curve starts (core.flip_continuation, core.torus_continuation).

The branch from a Hopf point is walked towards an end; a multiplier through the unit
circle between two points is judged (core.continuation.judged_crossing: beyond the
multipliers' uncertainty on both sides, located on corrected orbits) once WIDEN more
points are walked past it, or the walk has ended: the judge may widen a side by up to
WIDEN points when the nearest are within the uncertainty, and a candidate judged as soon
as it is walked has no points after it. (On the 3-slip branch at tau = 10 the torus at
k = 9.8623 is undetermined from the points at 9.781 and 10.280 alone, |mu| - 1 = -7.6e-5
uncertain by 8.4e-6 at the latter, and real with the point at 10.779.)
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TypeVar

from core.branch_start import BranchSpec, past_end, start
from core.continuation import Bifurcation, Branch, judged_crossing
from core.fold_continuation import FoldCurve
from core.multiplier_crossing import WIDEN, crossing_multiplier
from core.orbit import OrbitError
from core.params import Params


def first_crossing(spec: BranchSpec, kind: str, candidate: Callable[[complex], bool]
                   ) -> tuple[Branch, Bifurcation, int]:
    """The branch of ``spec`` walked until a crossing of ``kind`` (period-doubling, torus)
    is judged real: the branch, the bifurcation and the index of the point after it.
    ``candidate`` says which crossing multipliers (at the point after) may be one.
    OrbitError when the branch ends, or passes its end, with none."""
    what = "period doubling" if kind == "period-doubling" else "torus bifurcation"
    branch, _ = start(spec)
    branch.first()
    turns: set[int] = set()
    pending: list[int] = []
    ended = ""
    while not ended:
        try:
            point = branch.advance(1e-9)
        except OrbitError as exc:
            ended = f": {exc}"
            point = None
        last = len(branch.points) - 1
        if point is not None:
            if branch.points[last - 1].tangent_p * point.tangent_p < 0:
                turns.add(last)
            moved = crossing_multiplier(branch.points[last - 1].multipliers, point.multipliers)
            if moved is not None and candidate(moved[1]):
                pending.append(last)
            if past_end(spec, branch.points[0].value, point):
                ended = f" up to {spec.end:g}"
            elif last >= spec.max_points:
                ended = f" within {spec.max_points} points"
        while pending and (ended or pending[0] + WIDEN <= last):
            i = pending.pop(0)
            found = judged_crossing(branch, i, turns)
            if found is not None and found.type == kind:
                return branch, found, i
    raise OrbitError(f"no {what} on the branch in {spec.name}{ended}")


def branch_dt(p: Params, second: str, reach: float, dt: float) -> float:
    """The grid step of the branch a curve in (., ``second``) starts from: ``dt``, or finer
    when ``second`` is tau and the curve goes to a larger tau: along the curve the delay
    grid keeps its N = tau / dt points (core.fold_continuation), so N is chosen for the
    larger tau and dt stays at most the one asked for (as core.fold_start does)."""
    if second != "tau" or reach <= p.tau:
        return dt
    return p.tau / math.ceil(reach / dt - 1e-9)


def towards(p: Params, second: str, reach: float) -> float:
    """The direction a curve starting at ``p`` goes in ``second`` to reach ``reach``."""
    return 1.0 if reach > getattr(p, second) else -1.0


#: A curve started at a crossing (core.flip_continuation's, core.torus_continuation's).
C = TypeVar("C", bound=FoldCurve)
#: The first real crossing of a kind on the branch from a Hopf point: (params, name, dt,
#: end, hopf_branch, max_points, branch_step) -> (branch, crossing, index of the point
#: after it).
First = Callable[[Params, str, float, float, int, int, float], tuple[Branch, Bifurcation, int]]


def start_at_crossing(first: First, curve_at: Callable[..., C], spec_params: Params,
                      names: tuple[str, str], dt: float, end: float, reach: float,
                      step: float, max_step: float, hopf_branch: int, max_points: int,
                      branch_step: float) -> C:
    """A curve's start at the first real crossing on the branch in names[0] from the
    ``hopf_branch``-th Hopf point (``first``, up to ``end``), corrected into the curve in
    names[1] by ``curve_at`` (branch, crossing, second, step, max_step, after=index), which
    goes towards ``reach`` on the branch's grid chosen for it (``branch_dt``)."""
    branch, found, after = first(spec_params, names[0],
                                 branch_dt(spec_params, names[1], reach, dt), end,
                                 hopf_branch, max_points, branch_step)
    curve = curve_at(branch, found, names[1], step, max_step, after=after)
    curve.direction = towards(spec_params, names[1], reach)
    return curve


__all__ = ["branch_dt", "first_crossing", "start_at_crossing", "towards"]
