"""A curve walk that passes its end keeps the point past it when the point at the end
itself cannot be corrected (core.fold_continuation.step), instead of raising out of the
walk (a worker would have failed the whole curve)."""

from __future__ import annotations

import numpy as np

from core.floquet import Multipliers
from core.fold_continuation import CurvePoint, step
from core.orbit import OrbitError


def _point(second: float) -> CurvePoint:
    return CurvePoint(1.0, second, 5.0, 2.0, 0.0, Multipliers(np.array([1.0 + 0j]), 0, 1.0), 2)


class _Walk:
    """What ``step`` asks of a curve: one more point past tau = 10.5, and a Newton that
    fails at 10.5 exactly."""

    what, end, direction, names = "fold", "", 1.0, ("k", "tau")

    def __init__(self) -> None:
        self.points = [_point(10.2)]
        self.y, self.t = np.array([0.0, 1.0, 10.2]), np.array([0.0, 0.0, 1.0])

    def advance(self, min_step: float) -> CurvePoint:
        self.points.append(_point(10.6))
        self.y = np.array([0.0, 1.0, 10.6])
        return self.points[-1]

    def correct(self, y: np.ndarray, t: np.ndarray | None):
        raise OrbitError("Newton did not converge")

    def ended(self, point: CurvePoint) -> str:
        return ""


def test_a_walk_past_its_end_keeps_the_last_point_when_the_end_cannot_be_corrected():
    walk = _Walk()
    point = step(walk, 10.5, 10)  # type: ignore[arg-type]
    assert point is not None and point.second == 10.6
    assert [p.second for p in walk.points] == [10.2, 10.6]
    assert walk.end.startswith("passed tau = 10.5 (the last point at 10.6")
    assert "Newton did not converge" in walk.end
    assert step(walk, 10.5, 10) is None  # type: ignore[arg-type]
