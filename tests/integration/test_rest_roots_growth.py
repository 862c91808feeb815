"""The leading characteristic root (``slopetui roots``) against an independent measure: a
simulation started next to the rest state grows at the root's rate while it stays linear."""

from __future__ import annotations

import numpy as np
import pytest

from core.params import Params
from core.rest_stability import rest_roots
from core.solve import SolverSettings, simulate

pytestmark = pytest.mark.computation  # only computes: beside the slow tiers (tests/xdist_plan.py)


def test_a_run_next_to_an_unstable_rest_state_grows_at_the_leading_root() -> None:
    """tau = 2, k = 11.868 (1.3 k_H: one unstable pair, 0.05304 +- 2.612i, the next root at
    Re -0.286): from delta = 1e-6, RK4 at dt 1e-3, the oscillation's peak-to-peak per
    period grows from ~1e-6 by e^5.3 over t = 50-150, still far inside the linear range;
    its log-linear slope is the root's real part, its period 2 pi / Im."""
    p = Params(k=11.868, tau=2.0, delta=1e-6)
    lead = rest_roots(p)[0].value
    tr = simulate(p, SolverSettings(method="rk4", dt=1e-3, t_end=150.0, window=100.0, lyap=False))
    t, m_y = tr.window_t, tr.window[1]
    period = 2 * np.pi / lead.imag
    edges = np.arange(t[0], t[-1] - period, period)
    mids, spans = [], []
    for a in edges:
        part = m_y[(t >= a) & (t < a + period)]
        mids.append(a + period / 2)
        spans.append(float(np.ptp(part)))
    slope = np.polyfit(mids, np.log(spans), 1)[0]
    assert abs(slope - lead.real) < 0.02 * lead.real, (slope, lead)
    ups = t[1:][(m_y[:-1] < np.mean(m_y)) & (m_y[1:] >= np.mean(m_y))]
    assert abs(np.median(np.diff(ups[-10:])) - period) < 0.01 * period
