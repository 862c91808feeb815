"""How core.certify decides an orbit's minimal period across two steps (_minimal), on a
period map whose shots over T / j miss by what the test sets: T / j where the miss falls
as a scheme's error falls, T where it does not fall, undetermined between."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

import core.shooting
from core.certify import SUBPERIOD_TOL, _Attempt, _minimal, _periodic
from core.orbit import Grid

N = 50                                       # delay steps: a state of 2 N + 4 numbers
G = Grid(0.01, N)
#: m_y over one period of the long orbit, sampled every step: 4 equal slips (maxima)
M_Y = np.sin(np.linspace(0.0, 8 * np.pi, 801)) + 1.0


class Map:
    """A period map whose shot over T / j from z misses z by ``misses[j]`` (weighted
    norm, relative to the amplitude), and by 1 elsewhere."""

    def __init__(self, misses: dict[int, float]) -> None:
        self.g = G
        self.misses = misses

    def shoot(self, z: np.ndarray, T: float) -> SimpleNamespace:
        j = round(8.0 / T)
        miss = self.misses.get(j, 1.0) * float(np.ptp(M_Y))
        # the weighted norm of a shift of the first entry (weight 1) is the shift
        value = z.copy()
        value[0] += miss
        return SimpleNamespace(value=value, d_dT=np.zeros_like(z))


def solution(period: float = 8.0) -> SimpleNamespace:
    traj = np.zeros((5, N + M_Y.size))
    traj[1, N:] = M_Y
    shot = SimpleNamespace(traj=traj, col=N + M_Y.size - 1)
    return SimpleNamespace(z=np.zeros(G.size), period=period, shot=shot)


@pytest.fixture
def corrected(monkeypatch):
    """core.shooting.correct replaced: it returns the period it was asked for."""
    asked: list[float] = []

    def correct(_pm, z, period, *_args, **_kw):
        asked.append(period)
        return solution(period)

    monkeypatch.setattr(core.shooting, "correct", correct)
    return asked


def coarse(closures: dict[int, float]) -> _Attempt:
    return _Attempt(certificate=None, retry=True, closures=closures, dt=0.01)


def test_a_clean_closure_is_the_period_at_once(corrected):
    sol, unsure, why = _minimal(Map({4: 0.1 * SUBPERIOD_TOL}), solution())
    assert corrected == [2.0] and sol.period == 2.0 and unsure == {} and why == ""


def test_a_small_miss_at_the_certifiers_step_is_left_to_a_finer_one(corrected):
    # the b = 22, k = 12, tau = 2 misses at dt 0.01 (T / 4 and T / 2 of its T / 8 ...)
    sol, unsure, why = _minimal(Map({4: 1.8e-4, 2: 2.7e-5}), solution())
    assert corrected == [] and sol.period == 8.0 and why == ""
    assert unsure == pytest.approx({4: 1.8e-4, 2: 2.7e-5}, rel=1e-9)


def test_a_large_miss_is_the_orbits_own(corrected):
    sol, unsure, why = _minimal(Map({4: 0.5, 2: 0.02}), solution())
    assert corrected == [] and sol.period == 8.0 and unsure == {} and why == ""


def test_at_the_finer_step_a_miss_that_fell_as_the_schemes_is_the_period(corrected):
    # 1.8e-4 -> 6.9e-7 (260 times, measured): below SUBPERIOD_TOL anyway; 1.8e-4 -> 4e-6
    # (45 times) is above it but fell as a scheme's error does
    for fine in (6.9e-7, 4e-6):
        corrected.clear()
        sol, unsure, why = _minimal(Map({4: fine}), solution(), coarse({4: 1.8e-4}))
        assert corrected == [2.0] and sol.period == 2.0 and why == "" and unsure == {}, fine


def test_at_the_finer_step_a_miss_that_did_not_fall_is_the_orbits_own(corrected):
    # the orbit's distinct maxima (2e-4 of the amplitude at k = 20, tau = 10) stay
    sol, unsure, why = _minimal(Map({4: 1.9e-4}), solution(), coarse({4: 2e-4}))
    assert corrected == [] and sol.period == 8.0 and why == "" and unsure == {}


def test_at_the_finer_step_a_miss_that_fell_too_little_is_undetermined(corrected):
    # 2e-4 -> 2e-5: 10 times, neither a scheme's fall (32) nor none (4)
    sol, unsure, why = _minimal(Map({4: 2e-5}), solution(), coarse({4: 2e-4}))
    assert corrected == [] and sol.period == 8.0 and unsure == {}
    assert why.startswith("period T = 8; a shot over T / 4 misses by 2.0e-04 of the "
                          "amplitude at dt 0.01 and 2.0e-05 at 0.01")
    assert math.isfinite(sol.period)


def test_the_retry_runs_at_a_quarter_of_the_step(monkeypatch):
    """_periodic tries once more, at dt / 4, only where the first attempt says a finer
    step may decide, and hands it the first attempt."""
    import core.certify as certify
    steps: list[tuple[float, bool]] = []

    def attempt(_tr, _s, g, coarse=None):
        steps.append((g.dt, coarse is not None))
        return _Attempt(certificate=f"at {g.dt:g}", retry=coarse is None, dt=g.dt)

    monkeypatch.setattr(certify, "_attempt", attempt)
    tr = SimpleNamespace(params=SimpleNamespace(tau=2.0), window_t=np.linspace(0, 1000, 100001),
                         window=None)
    assert _periodic(tr, None) == "at 0.0025"
    assert steps == [(0.01, False), (0.0025, True)]
    steps.clear()                                # the first attempt alone (the benchmarks')
    assert _periodic(tr, None, retry=False) == "at 0.01"
    assert steps == [(0.01, False)]
