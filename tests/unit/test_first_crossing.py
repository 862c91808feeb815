"""Where a period-doubling or torus curve starts: the branch's grid is chosen for the
larger tau the curve will reach (its N = tau / dt stays fixed along the curve), and the
curve goes towards the end asked."""

from __future__ import annotations

import pytest

from core.first_crossing import branch_dt, towards
from core.params import Params


@pytest.mark.parametrize(("second", "reach", "dt"), [
    ("tau", 20.0, 10.0 / 2000), ("tau", 10.5, 10.0 / 1050), ("tau", 5.0, 0.01),
    ("k", 20.0, 0.01)])
def test_the_branch_grid_keeps_dt_at_most_the_one_asked_along_the_curve(second, reach, dt):
    assert branch_dt(Params(tau=10.0), second, reach, 0.01) == pytest.approx(dt, rel=1e-12)


def test_the_curve_goes_towards_its_end():
    assert towards(Params(tau=10.0), "tau", 5.0) == -1.0
    assert towards(Params(tau=10.0), "tau", 12.0) == 1.0
