"""A shot refuses a period no orbit has, as an OrbitError (which a continuation answers by
a shorter step), before it allocates anything: a Newton step far off an orbit asked for a
period of ~1e9 in a continuation in c and died of a MemoryError."""

from __future__ import annotations

import math
import tracemalloc

import numpy as np
import pytest

from core.orbit import MAX_SHOT_STEPS, Grid, OrbitError, PeriodMap
from core.params import Params


@pytest.mark.parametrize("period", [1e9, math.inf, math.nan, 1.01 * MAX_SHOT_STEPS * 0.01])
def test_a_period_beyond_one_shot_is_refused_before_anything_is_allocated(period):
    pm = PeriodMap(Params(tau=2.0, k=12.0), Grid(0.01, 200))
    z = np.zeros(pm.g.size)
    tracemalloc.start()
    try:
        with pytest.raises(OrbitError, match="beyond one shot"):
            pm.shoot(z, period)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 1_000_000


def test_a_period_within_it_is_integrated():
    pm = PeriodMap(Params(tau=2.0, k=12.0), Grid(0.01, 200))
    shot = pm.shoot(np.zeros(pm.g.size), 3.0)
    assert shot.value.shape == (pm.g.size,)
