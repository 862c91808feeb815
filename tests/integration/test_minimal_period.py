"""The large-b points a referee named are period-1 orbits, against an independent RK4.

At delta = 0.1, t_end 2e4 (Euler, dt 1e-3, the paper's) the tool called (b, k, tau) =
(15, 12, 6) period-2, (18, 12, 10) period-4 and (17, 10, 7) period-3: the timing noise of
flat maxima taken for an alternation (core.returns.SAMPLE_TIME_NOISE). The reference here
owes nothing to core: eqs. 6a-6e written again from the paper, classical RK4 at dt 0.005
(half the orbit step) with the delayed m_x at the half step from a cubic Lagrange
interpolant on the m_x grid (the kernels use a Hermite one), and its own maxima (a
parabola through three samples at dt 0.005)."""

from __future__ import annotations

import numpy as np
import pytest
from numba import njit

from core.params import Params
from core.point import run_point
from core.solve import SolverSettings

pytestmark = pytest.mark.computation  # only computes: beside the slow tiers (tests/xdist_plan.py)

H = 0.005          # the reference's step
T_END = 2e4
TAIL = 400.0       # where its maxima are read


@njit(cache=False)
def _field(m_x, m_y, s_x, s_y, u, x_tau, a, b, c, d, k, v):
    f1 = 3 * a * v * v - 2 * b * v + c
    q = 3 * a * v - b
    g = f1 + 2 * q * m_y + 3 * a * (m_y * m_y + s_y)
    return (m_y,                                                                       # (6a)
            -f1 * m_y - q * m_y ** 2 - a * m_y ** 3 - q * s_y - 3 * a * m_y * s_y
            + k * (x_tau - m_x),                                                       # (6b)
            2 * u,                                                                     # (6c)
            -2 * s_y * g - 2 * k * u + 2 * d,                                          # (6d)
            -u * g - k * s_x + s_y)                                                    # (6e)


@njit(cache=False)
def _rk4(a, b, c, d, k, v, tau, delta, h, n_steps, n_tail):
    """m_y over the last n_tail steps, from eq. 19 with the constant history."""
    n = int(tau / h + 0.5)
    xs = np.full(n + n_steps + 1, delta)       # m_x at every step from -tau
    z = np.full(5, delta)                      # (19)
    out = np.empty(n_tail)
    for j in range(n_steps):
        o = j                                  # the column of t - tau (xs index j is -tau + j h)
        x0, x1 = xs[o], xs[o + 1]
        xm1 = xs[o - 1] if o >= 1 else x0
        x2 = xs[o + 2] if o + 2 <= n + j else x1 + (x1 - x0)
        xh = (-xm1 + 9 * x0 + 9 * x1 - x2) / 16   # cubic Lagrange midpoint
        k1 = _field(z[0], z[1], z[2], z[3], z[4], x0, a, b, c, d, k, v)
        k2 = _field(z[0] + h / 2 * k1[0], z[1] + h / 2 * k1[1], z[2] + h / 2 * k1[2],
                    z[3] + h / 2 * k1[3], z[4] + h / 2 * k1[4], xh, a, b, c, d, k, v)
        k3 = _field(z[0] + h / 2 * k2[0], z[1] + h / 2 * k2[1], z[2] + h / 2 * k2[2],
                    z[3] + h / 2 * k2[3], z[4] + h / 2 * k2[4], xh, a, b, c, d, k, v)
        k4 = _field(z[0] + h * k3[0], z[1] + h * k3[1], z[2] + h * k3[2],
                    z[3] + h * k3[3], z[4] + h * k3[4], x1, a, b, c, d, k, v)
        for r in range(5):
            z[r] += h / 6 * (k1[r] + 2 * k2[r] + 2 * k3[r] + k4[r])
        xs[n + j + 1] = z[0]
        if j + 1 >= n_steps - n_tail + 1:
            out[j + 1 - (n_steps - n_tail + 1)] = z[1]
    return out


def reference_maxima(p: Params) -> tuple[np.ndarray, np.ndarray]:
    """Times and heights of the maxima of m_y over the reference's last TAIL time units."""
    n_tail = int(TAIL / H)
    y = _rk4(p.a, p.b, p.c, p.d, p.k, p.v, p.tau, p.delta, H, int(T_END / H), n_tail)
    i = np.nonzero((y[1:-1] > y[:-2]) & (y[1:-1] >= y[2:]))[0] + 1
    y0, y1, y2 = y[i - 1], y[i], y[i + 1]
    off = 0.5 * (y0 - y2) / (y0 - 2 * y1 + y2)
    return (i + off) * H, y1 - 0.25 * (y0 - y2) * off


@pytest.mark.parametrize(("b", "k", "tau", "old"), [(15, 12, 6, "period-2"),
                                                    (18, 12, 10, "period-4"),
                                                    (17, 10, 7, "period-3")])
def test_large_b_orbits_are_period_1(b, k, tau, old):
    p = Params(b=b, k=k, tau=tau, delta=0.1)
    t, heights = reference_maxima(p)
    amplitude = 2 * float(np.max(np.abs(heights)))  # a scale only
    spacing = np.diff(t)
    # the reference: one maximum a period, equally spaced, all of one height
    assert np.ptp(heights) < 1e-6 * amplitude
    assert np.ptp(spacing) < 1e-3 * spacing.mean()   # H / 2 in time at most: its parabola
    period = float(spacing.mean())

    r = run_point(p, SolverSettings(t_end=T_END))     # Euler, dt 1e-3: the paper's
    s = r.summary
    assert s.regime == "oscillatory", f"was {old}: {s.detail}"
    assert (s.period_count, s.maxima_per_period) == (1, 1), s.detail
    assert s.detail.startswith("period-1, 1 maximum")
    # certified on RK4 at dt 0.01: the reference's period to RK4's accuracy
    assert r.certificate.certified, r.certificate.text
    assert r.certificate.slips == 1
    assert s.period == pytest.approx(period, rel=2e-6)   # measured 1.7e-7 to 2.7e-7
    assert all(abs(complex(*m)) < 1 for m in r.as_record()["multipliers"])


def test_a_square_wave_s_plateau_is_one_slip_a_period():
    # k = 7, tau = 60: the stick phase is a plateau of m_y flat to round-off, whose ripple
    # (1.3e-12 A) made RK4's window "no return, band still moving" (complex)
    p = Params(k=7, tau=60, delta=0.1)
    t, heights = reference_maxima(p)
    y_range = float(np.max(heights) - np.min(heights))
    slips = t[heights > np.min(heights) + 0.5 * y_range]     # the reference's real maxima
    low = heights[heights <= np.min(heights) + 0.5 * y_range]
    assert np.ptp(low) < 1e-9 * y_range                       # the rest: the plateau's ripple
    period = float(np.diff(slips).mean())
    assert np.ptp(np.diff(slips)) < 1e-3 * period

    r = run_point(p, SolverSettings(t_end=T_END, method="rk4", dt=0.01))
    s = r.summary
    assert (s.regime, s.period_count, s.maxima_per_period) == ("oscillatory", 1, 1), s.detail
    assert r.certificate.certified and r.certificate.slips == 1, r.certificate.text
    assert s.period == pytest.approx(period, rel=2e-6)
