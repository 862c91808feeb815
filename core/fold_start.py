"""Where a fold-of-cycles curve starts: the fold of the one-parameter branch born at a Hopf
point (core.continuation), corrected onto the minimally augmented system
(core.fold_continuation); the same fold continued in another pair of parameters
(``switched``); and a fold in a parameter with no Hopf start (d, v), reached along the fold
surface from a fold in k (``_via_k``).
"""

from __future__ import annotations

import math

import numpy as np

from core.continuation import Branch
from core.fold_continuation import FoldCurve, walk
from core.orbit import Grid, OrbitError, PeriodMap
from core.params import Params
from core.shooting import weighted_dot

#: The parameters with a Hopf point to start a branch from (core.hopf_start).
HOPF_STARTS = ("k", "tau", "a", "b", "c")


def start_at_fold(p: Params, names: tuple[str, str], reach: float, dt: float = 0.01,
                  step: float = 0.05, max_step: float = 0.5, hopf_branch: int = 1,
                  n_delay: int | None = None) -> FoldCurve:
    """The curve's start: the one-parameter branch in names[0] from the Hopf point at p,
    walked to its first turn (core.continuation), the point before the turn corrected onto
    the fold with names[1] fixed. ``reach`` is the other end of names[1]'s range (the grid
    is chosen for the larger tau of the two). A fold in a parameter with no Hopf start
    (d, v) is reached along the fold surface instead: see ``_via_k``."""
    from core.fold_curve import step_sizes  # the one-parameter branch's own steps

    name, second = names
    if n_delay is None:
        n_delay = Grid.of(p, dt).n_delay
        if second == "tau":
            n_delay = math.ceil(max(p.tau, reach) / dt - 1e-9)
    if name not in HOPF_STARTS:
        return _via_k(p, names, reach, dt, step, max_step, n_delay, hopf_branch)
    dt_start = p.tau / n_delay
    first, largest = step_sizes(p, name)
    branch, _ = Branch.from_hopf(p, name, dt_start, 1e-3, first, largest, hopf_branch)
    n_delay = branch.g0.n_delay
    branch.first()
    for _ in range(400):
        branch.advance(1e-9)
        pts = branch.points
        if pts[-2].tangent_p * pts[-1].tangent_p < 0:
            break
    else:
        raise OrbitError(f"the branch in {name} from the Hopf point has no fold within "
                         "400 points")
    y_b, t_b = branch.states[-2]
    n = branch.g0.size
    q = branch.map_at(float(y_b[-1])).p
    g = branch.g0 if name != "tau" else Grid(q.tau / n_delay, n_delay)
    pm = PeriodMap(q, g)
    shot = pm.shoot(y_b[:n], float(y_b[n]))
    c = t_b[:n + 1] / math.sqrt(weighted_dot(t_b[:n + 1], t_b[:n + 1],
                                             np.concatenate((g.weights, [1.0]))))
    y0 = np.concatenate((y_b, [getattr(p, second)]))
    return FoldCurve(p.with_(**{name: float(y_b[-1])}), names, n_delay, g.dt, y0, c,
                     y_b[:n].copy(), shot.d_dT.copy(), step, max_step,
                     direction=1.0 if reach > getattr(p, second) else -1.0)


def switched(curve: FoldCurve, names: tuple[str, str], towards: float, step: float = 0.05,
             max_step: float = 0.5) -> FoldCurve:
    """The same fold of cycles, continued from its last point in another pair of
    parameters: the bordered system takes names[0]'s column (any parameter whose column is
    outside F_x's range will do), and the curve starts towards names[1] = ``towards``."""
    p = curve.params(curve.y)
    n = curve.size
    y = np.concatenate((curve.y[:n + 1], [getattr(p, names[0]), getattr(p, names[1])]))
    return FoldCurve(p, names, curve.n_delay, curve.grid(p).dt, y, curve.c.copy(),
                     curve.z_ref.copy(), curve.zdot_ref.copy(), step, max_step,
                     direction=1.0 if towards > getattr(p, names[1]) else -1.0)


def _via_k(p: Params, names: tuple[str, str], reach: float, dt: float, step: float,
           max_step: float, n_delay: int, hopf_branch: int = 1) -> FoldCurve:
    """The fold in names[0] (d or v: no Hopf start) at p: the fold in k at p's other
    values, continued in (names[0], k) at p's tau until k = p.k, where it is a fold in
    names[0]; from there the curve in ``names``. Raises OrbitError when that path meets
    the Hopf curve first (a Bautin point: no fold in names[0] at this k; at tau = 10 the
    fold in k moves from 1.214 at d = 1e-4 to the Hopf curve at d = 2.23, k = 6.41)."""
    name = names[0]
    in_k = start_at_fold(p, ("k", name), getattr(p, name), dt, step, max_step, hopf_branch,
                         n_delay=n_delay)
    in_k.first()
    along = switched(in_k, (name, "k"), p.k, step, max_step)
    for _ in walk(along, p.k, 400):
        pass
    if not along.end.startswith("reached"):
        raise OrbitError(f"no fold of cycles in {name} at k = {p.k:g}: from the fold in k at "
                         f"{name} = {getattr(p, name):g} the fold surface ended at {name} = "
                         f"{along.points[-1].first:.6g}, k = {along.points[-1].second:.6g} "
                         f"({along.end})")
    return switched(along, names, reach, step, max_step)


__all__ = ["HOPF_STARTS", "start_at_fold", "switched"]
