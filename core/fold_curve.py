"""The fold of cycles in a second parameter: where the bistable band ends.

Between the fold of cycles and the Hopf point of a subcritical branch a stable cycle and
the stable steady state coexist: the outcome depends on the initial state, the paper's
"conditionally stable" slopes. This module traces the fold point by point along a second
parameter (tau by default): at each value the branch is continued from the Hopf point
(core.continuation.Branch.from_hopf) until the parameter turns, and the turn is located
(core.continuation.locate_fold, to ~1e-6). Each point is an independent continuation, so
one failure leaves the others standing.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass

from core.continuation import Branch, bifurcations, criticality
from core.orbit import OrbitError
from core.params import ParameterError, Params

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
    """The Hopf point in ``name`` at p and the fold of cycles of the branch born there."""
    branch, hopf = Branch.from_hopf(p, name, dt, 1e-3, 0.02 * STEP_FRACTION * abs(hopf_scale(p, name)),
                                    STEP_FRACTION * abs(hopf_scale(p, name)))
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
    return FoldPoint(p.tau, hopf.value, folds[0] if folds else None,
                     criticality(branch.points), "" if folds else "no turn within the search")


def hopf_scale(p: Params, name: str) -> float:
    """A size for the steps of a branch in ``name``: the parameter's value, at least 1."""
    return max(1.0, abs(getattr(p, name)))


def fold_curve(p: Params, values: Iterable[float], second: str = "tau", name: str = "k",
               dt: float = 0.01) -> Iterator[FoldPoint]:
    """The fold of cycles in ``name`` for each value of ``second`` (tau by default)."""
    for value in values:
        try:
            q = p.with_(**{second: value})
            if name == "k":
                from core.stability import hopf_k
                q = q.with_(k=hopf_k(q.tau, q.F1))
            point = fold_of_cycles(q, name, dt)
        except (OrbitError, ParameterError) as exc:
            yield FoldPoint(value, float("nan"), None, "", str(exc))
            continue
        yield FoldPoint(value, point.hopf, point.fold, point.criticality, point.note)
