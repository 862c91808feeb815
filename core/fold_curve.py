"""The fold of cycles in a second parameter: where the bistable band ends.

Between the fold of cycles and the Hopf point of a subcritical branch a stable cycle and
the stable steady state coexist: the outcome depends on the initial state, the paper's
"conditionally stable" slopes. This module traces the fold point by point along a second
parameter (tau by default): at each value the branch is continued from the Hopf point
(core.continuation.Branch.from_hopf) until the parameter turns, and the fold is located
(core.continuation.locate_fold: the fold's minimally augmented system from the point before
the turn). Each point is an independent continuation, so one failure leaves the others
standing. core.fold_continuation continues the fold as one curve instead: from tau = 10 to
2, 33 points in 6.4 s CPU where nine of these take 7.2 s (benchmarks/bench_fold_curve.py).
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass

from core.continuation import Branch, bifurcations, criticality
from core.orbit import OrbitError
from core.params import Params
from core.stability import hopf_friction, hopf_k

#: Branch points a search for the fold may take before giving up (the fold at tau = 10
#: is reached in ~30 points from the Hopf point).
FOLD_SEARCH_POINTS = 200
#: The branch's largest step, as a fraction of the Hopf value of the parameter.
STEP_FRACTION = 0.08


@dataclass(frozen=True)
class FoldPoint:
    """The fold of cycles at one value of the second parameter (None when the branch
    has none: a supercritical Hopf point, or no turn within the search)."""

    second: float
    hopf: float
    fold: float | None
    criticality: str
    note: str = ""


def fold_of_cycles(p: Params, name: str = "k", dt: float = 0.01) -> FoldPoint:
    """The Hopf point in ``name`` at p and the fold of cycles of the branch born there,
    when it is subcritical: the fold that, with the Hopf point, bounds the band where
    rest and oscillation coexist (None for a supercritical branch, see below)."""
    first, largest = step_sizes(p, name)
    branch, hopf = Branch.from_hopf(p, name, dt, 1e-3, first, largest)
    branch.first()
    turned = False
    try:
        for _ in range(FOLD_SEARCH_POINTS):
            branch.advance(1e-9)
            pts = branch.points
            if pts[-2].tangent_p * pts[-1].tangent_p < 0:
                turned = True
            elif turned:
                break  # one point past the turn, for the parabola
    except OrbitError as exc:
        return FoldPoint(p.tau, hopf.value, None, criticality(branch.points), str(exc))
    folds = [b.value for b in bifurcations(branch) if b.type == "fold"]
    critical = criticality(branch.points)
    if folds and critical == "supercritical":
        # The stable cycles born at a supercritical Hopf point coexist with no stable rest:
        # a turn further on bounds no band where the initial state decides, which is what
        # this curve draws. (Found in (b, tau) at k = 12, tau = 2: Hopf b = 3.68, a turn at
        # b = 22.3, where F(v+) <= 0, eq. 12.)
        return FoldPoint(p.tau, hopf.value, None, critical,
                         f"supercritical: the branch turns at {name} = {folds[0]:.6g}, "
                         "which bounds no bistable band")
    return FoldPoint(p.tau, hopf.value, folds[0] if folds else None, critical,
                     "" if folds else "no turn within the search")


#: The largest step of a branch in a friction parameter. A step measured in the
#: parameter's own size let the branch jump sheets: in a at k = 12, tau = 5 (a_H = 46.6,
#: steps up to 3.7) its second orbit landed on the stable sheet past the fold, 0.68 above
#: the Hopf point, skipping the unstable orbits between them; with steps up to 0.5 it
#: walks them (amplitude 0.002 to 0.083) to the fold at 47.2497.
FRICTION_MAX_STEP = 0.5


def step_sizes(p: Params, name: str) -> tuple[float, float]:
    """The first and the largest step of a branch from the Hopf point in ``name``."""
    largest = STEP_FRACTION * hopf_scale(p, name)
    if name in ("a", "b", "c"):
        largest = min(largest, FRICTION_MAX_STEP)
    return 0.02 * largest, largest


def hopf_scale(p: Params, name: str) -> float:
    """A size for the steps of a branch in ``name``: the parameter's value, at least 1."""
    return max(1.0, abs(getattr(p, name)))


def fold_curve(p: Params, values: Iterable[float], second: str = "tau", name: str = "k",
               dt: float = 0.01) -> Iterator[FoldPoint]:
    """The fold of cycles in ``name`` for each value of ``second`` (tau by default), each
    from the Hopf point in ``name`` there (the noise-free one seeds it: core.stability's
    k_H for k, its friction curves for a, b and c)."""
    for value in values:
        try:
            q = p.with_(**{second: value})
            if name == "k":
                q = q.with_(k=hopf_k(q.tau, q.F1))
            elif name in ("a", "b", "c"):
                q = q.with_(**{name: hopf_friction(q, name)[0]})
            point = fold_of_cycles(q, name, dt)
        except ValueError as exc:  # OrbitError, ParameterError, or no Hopf point here
            yield FoldPoint(value, float("nan"), None, "", str(exc))
            continue
        yield FoldPoint(value, point.hopf, point.fold, point.criticality, point.note)
