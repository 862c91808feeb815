"""The leading multipliers of an orbit with more than ten near or outside the circle."""

from __future__ import annotations

from core.floquet import multipliers
from core.orbit import PeriodMap
from core.params import Params
from core.periodic_orbit import find_orbit
from core.shooting import correct


def test_the_flow_multiplier_is_found_past_the_leading_ten():
    """The 6-slip orbit at k = 18, tau = 10 (period 1.7346) has ten multipliers of modulus
    1.0007 to 1.027, all above the flow's: the leading ten hold no flow multiplier, and
    the old code took 1.0007's pair for it (1e-0 from 1) and called the orbit 8 times
    unstable. Asked for ten, it computes more until the flow's is among them."""
    o = find_orbit(Params(k=18.0, tau=10.0, delta=1e-6), slips=6)
    pm = PeriodMap(o.params, o.grid)
    zdot = (pm.shoot(o.z, o.grid.dt).value - o.z) / o.grid.dt
    sol = correct(pm, o.z, o.period, o.z, zdot)
    m = multipliers(pm, sol.shot, 10)
    assert abs(m.flow - 1.0) < 1e-6        # measured 1.8e-7 (2.7e-9 at dt = 0.005)
    assert m.unstable_count == 10
    assert abs(o.multipliers.flow - 1.0) < 1e-6 and not o.stable


def test_more_multipliers_than_the_state_holds_stay_within_arpack_sizes() -> None:
    """A request for more multipliers than the reduced state has (the search for the flow's
    doubles its count) is cut to what ARPACK accepts (k + 1 < ncv <= n - 1), not an
    error: a continuation at tau = 54 doubled to the whole state and failed a run with
    "ncv must be k+1<ncv<=n"."""
    from core.floquet import _leading
    o = find_orbit(Params(k=37.6, tau=0.5))
    pm = PeriodMap(o.params, o.grid)
    n = o.grid.size
    m = _leading(pm, pm.shoot(o.z, o.period), n + 10, 150, 2000)
    assert len(m.values) == n - 3
    assert abs(m.flow - 1.0) < 1e-4
