"""Parameters, validation (field + allowed range, before anything runs), eqs. 1, 9-17."""

from __future__ import annotations

import math

import pytest

from core import ParameterError, Params, SolverSettings, friction_warnings
from core.params import fixed_points, friction, friction_extrema
from core.solve import make_grid


def test_defaults_are_eq_8():
    p = Params()
    assert (p.a, p.b, p.c, p.d, p.v) == (3.2, 7.2, 4.8, 1e-4, 0.1)
    assert p.F == pytest.approx(3.2e-3 - 7.2e-2 + 0.48)          # eq. 1 at v = 0.1
    assert p.F1 == pytest.approx(3.456)                            # eq. 10
    assert p.q == pytest.approx(-6.24)


@pytest.mark.parametrize(
    "field,value,allowed",
    [
        ("tau", -1.0, "tau >= 0"),
        ("d", -1e-4, "d >= 0"),
        ("k", -2.0, "k >= 0"),
        ("a", math.nan, "finite"),
        ("b", math.inf, "finite"),
        ("delta", "abc", "finite"),
    ],
)
def test_bad_parameter_names_field_and_range(field, value, allowed):
    with pytest.raises(ParameterError) as exc:
        Params(**{field: value})
    assert exc.value.field == field
    assert allowed in str(exc.value)


@pytest.mark.parametrize(
    "kwargs,field",
    [
        (dict(dt=0.0), "dt"),
        (dict(dt=-1e-3), "dt"),
        (dict(t_end=0.0), "t_end"),
        (dict(t_end=math.nan), "t_end"),
        (dict(window=2e5), "window"),
        (dict(window=0.0), "window"),
        (dict(method="midpoint"), "method"),
    ],
)
def test_bad_settings_name_field(kwargs, field):
    with pytest.raises(ParameterError) as exc:
        SolverSettings(**kwargs)
    assert exc.value.field == field


def test_dt_longer_than_tau_is_refused():
    with pytest.raises(ParameterError) as exc:
        make_grid(Params(tau=0.5), SolverSettings(dt=1.0))
    assert exc.value.field == "dt" and "tau = 0.5" in str(exc.value)


def test_grid_makes_tau_a_whole_number_of_steps():
    g = make_grid(Params(tau=0.25), SolverSettings(method="rk4", dt=0.03))
    assert g.n_delay == 9 and g.dt == pytest.approx(0.25 / 9)
    g = make_grid(Params(tau=10.0), SolverSettings())
    assert (g.n_delay, g.dt, g.n_steps) == (10000, 1e-3, 100_000_000)
    g = make_grid(Params(tau=0.0), SolverSettings(dt=0.5, t_end=10, window=2))
    assert g.n_delay == 0 and g.dt == 0.5


def test_default_point_breaks_no_constraint():
    assert friction_warnings(Params()) == []


def test_low_a_is_a_warning_not_an_error():
    p = Params(a=0.03)                       # the paper's Fig. 7 explores this
    warnings = friction_warnings(p)
    assert any("eq. 12" in w for w in warnings)


def test_constraint_intervals_of_eq_13():
    # eq. 13b: 6.788 < b < 7.838 keeps 3ac < b^2 < 4ac for default a, c
    assert friction_warnings(Params(b=6.79)) == []
    assert friction_warnings(Params(b=7.83)) == []
    assert any("eqs. 10, 12" in w for w in friction_warnings(Params(b=6.78)))
    assert any("eq. 12" in w for w in friction_warnings(Params(b=7.84)))
    assert any("eq. 11" in w for w in friction_warnings(Params(a=-1.0)))


def test_friction_extrema_are_stationary_points():
    p = Params()
    lo, hi = friction_extrema(p)
    assert (lo, hi) == pytest.approx((0.5, 1.0))                   # eq. 10 at defaults
    for v in (lo, hi):
        h = 1e-6
        slope = (friction(v + h, p.a, p.b, p.c) - friction(v - h, p.a, p.b, p.c)) / (2 * h)
        assert abs(slope) < 1e-8


def test_fixed_points_eq_14_to_17():
    assert fixed_points(Params(d=0.0)) == [dict(m_y=0.0, s_x=0.0, s_y=0.0, u=0.0)]
    assert fixed_points(Params(d=1e-4)) == []   # noise drives a drift instead
    # 3av - b = 0: the non-trivial branch of eq. 17 at v = b / (3a) = 0.75
    p = Params(v=0.75, d=1e-3, k=4.0)
    pts = fixed_points(p)
    assert len(pts) == 1
    s_y = pts[0]["s_y"]
    assert s_y > 0 and pts[0]["s_x"] == pytest.approx(s_y / p.k)
    assert 3 * p.a * s_y**2 + p.F1 * s_y - p.d == pytest.approx(0.0, abs=1e-15)   # eq. 14b
    r = math.sqrt((3 * p.v**2 - p.c / p.a) ** 2 + 12 * p.d / p.a)
    assert s_y == pytest.approx((3 * p.v**2 - p.c / p.a + r) / 6)                   # eq. 17


def test_runs_that_leave_the_fixed_point_rest_on_the_steady_sliding_branch():
    """High b opens a second steady state (core.params.sliding_branches); a run from near
    the fixed point settles on its larger root, as the (b, tau) presets showed."""
    from core import SolverSettings, run_point
    from core.params import sliding_branches

    assert sliding_branches(Params()) == ()  # none at the defaults of eq. 8
    p = Params(b=20.2895, k=12.0, tau=1.14737, delta=1e-6)
    low, high = sliding_branches(p)
    assert low == pytest.approx(0.885458, rel=1e-5) and high == pytest.approx(5.155011, rel=1e-6)
    r = run_point(p, SolverSettings(method="rk4", t_end=2000.0, window=200.0, lyap=False))
    assert r.summary.regime == "sliding" and r.summary.drift == pytest.approx(high, rel=1e-5)
