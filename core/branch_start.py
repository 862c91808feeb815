"""A continuation as a restartable computation: what it asks (BranchSpec), its first
point (start), and the same branch rebuilt from the points already computed (resume).

A worker computes a branch point by point and saves each one (its unknowns y, its unit
secant t, its multipliers and the step h that follows it); a worker that takes over a
branch whose first worker died rebuilds it from those and goes on. The rebuilt branch
predicts its next point from the same y, t and h, so it continues as if never stopped
(tests/unit/test_branch_jobs.py compares the two).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from core.continuation import Branch, BranchPoint, grid_at, params_at
from core.floquet import Multipliers
from core.hopf_start import HopfPoint
from core.orbit import Grid, PeriodMap
from core.params import Params
from core.periodic_orbit import find_orbit
from core.shooting import Solution

#: The amplitude of the first orbit of a branch from the Hopf point (peak-to-peak scale
#: of the critical eigenvector's m_x; small enough that the Hopf normal form holds: the
#: corrected orbit's parameter is within 1e-6 of the Hopf value at tau = 10).
HOPF_EPS = 1e-3
#: The first step from the Hopf point, and from a simulated orbit as a fraction of the
#: largest step: short, so that the first secant is taken close to the start.
HOPF_FIRST_STEP, ORBIT_FIRST_STEP = 0.02, 0.05
#: Newton's last resort: a step shorter than this ends the branch.
MIN_STEP = 1e-7


@dataclass(frozen=True)
class BranchSpec:
    """A continuation in parameter ``name`` from ``params``: from its Hopf point
    (``from_hopf``) or from the orbit a simulation from eq. 19 settles on, with grid step
    ``dt``, until the parameter passes ``end`` (None: no end but the others), at most
    ``max_points`` points, steps of at most ``max_step`` along the branch."""

    params: Params
    name: str
    dt: float
    from_hopf: bool
    end: float | None = None
    max_points: int = 300
    max_step: float = 0.5
    hopf_branch: int = 1


def start(spec: BranchSpec) -> tuple[Branch, HopfPoint | None]:
    """The branch's first corrected orbit: at the Hopf point (then onward in the direction
    of growing amplitude), or on the simulated orbit heading towards ``end`` (down when
    ``end`` is below the start, else up). Raises OrbitError when there is no orbit."""
    if spec.from_hopf:
        return Branch.from_hopf(spec.params, spec.name, spec.dt, HOPF_EPS, HOPF_FIRST_STEP,
                                spec.max_step, spec.hopf_branch)
    orbit = find_orbit(spec.params, spec.dt)
    shot = PeriodMap(spec.params, orbit.grid).shoot(orbit.z, orbit.period)
    value = getattr(spec.params, spec.name)
    direction = -1.0 if spec.end is not None and spec.end < value else 1.0
    sol = Solution(orbit.z, orbit.period, shot, orbit.newton_steps, orbit.residual, 0)
    return Branch.from_orbit(spec.params, orbit.grid, spec.name, sol, direction,
                             ORBIT_FIRST_STEP * spec.max_step, spec.max_step), None


def past_end(spec: BranchSpec, first: float, point: BranchPoint) -> bool:
    """Has the branch, started at parameter value ``first``, passed ``spec.end``?"""
    return spec.end is not None and (point.value - spec.end) * (spec.end - first) >= 0


@dataclass(frozen=True)
class SavedPoint:
    """What a branch point leaves behind to be resumed from: y = (z, T, p), the unit
    secant t that reached it, its multipliers, its amplitude, and the step h the branch
    will try next."""

    y: np.ndarray
    t: np.ndarray
    amplitude: float
    multipliers: Multipliers
    step: float

    @staticmethod
    def of(branch: Branch) -> SavedPoint:
        """The branch's last point."""
        y, t = branch.states[-1]
        point = branch.points[-1]
        return SavedPoint(y, t, point.amplitude, point.multipliers, branch.h)

    def point(self, n: int) -> BranchPoint:
        return BranchPoint(float(self.y[-1]), float(self.y[n]), self.amplitude,
                           self.multipliers, self.y[:n].copy(), float(self.t[-1]))


def resume(spec: BranchSpec, saved: list[SavedPoint]) -> Branch:
    """The branch rebuilt from its saved points, ready to advance from the last. Its grid
    has the saved states' N (len(y) = 2N + 6); only N matters to a branch in tau, whose
    dt follows tau (core.continuation.grid_at)."""
    first, last = saved[0], saved[-1]
    base = params_at(spec.params, spec.name, float(first.y[-1]))
    n_delay = (first.y.size - 6) // 2
    grid = Grid(base.tau / n_delay, n_delay)
    n = grid.size
    value = float(last.y[-1])
    q = params_at(base, spec.name, value)
    shot = PeriodMap(q, grid_at(grid, q, spec.name)).shoot(last.y[:n], float(last.y[n]))
    branch = Branch(base, grid, spec.name, last.y.copy(), last.t, shot, last.step,
                    spec.max_step)
    branch.t = last.t.copy()  # already unit: kept to the bit, as the first worker had it
    branch.points = [s.point(n) for s in saved]
    branch.states = [(s.y.copy(), s.t.copy()) for s in saved]
    return branch


__all__ = ["BranchSpec", "SavedPoint", "past_end", "resume", "start"]
