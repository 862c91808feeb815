"""Parameters, validation (field + allowed range, before anything runs), eqs. 1, 9-17."""

from __future__ import annotations

import math

import pytest

from core.params import ParameterError, Params, fixed_points, friction, friction_extrema, friction_warnings
from core.solve import (
    MAX_RUN_BYTES,
    MAX_STEPS,
    RING_BYTES,
    SAMPLE_BYTES,
    LimitError,
    SolverSettings,
    make_grid,
    memory_of,
    validate_run,
)


def test_defaults_are_eq_8():
    p = Params()
    assert (p.a, p.b, p.c, p.d, p.v) == (3.2, 7.2, 4.8, 1e-4, 0.1)
    assert pytest.approx(3.2e-3 - 7.2e-2 + 0.48) == p.F          # eq. 1 at v = 0.1
    assert pytest.approx(3.456) == p.F1                            # eq. 10
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
    from core.params import sliding_branches
    from core.point import run_point
    from core.solve import SolverSettings

    assert sliding_branches(Params()) == ()  # none at the defaults of eq. 8
    p = Params(b=20.2895, k=12.0, tau=1.14737, delta=1e-6)
    low, high = sliding_branches(p)
    assert low == pytest.approx(0.885458, rel=1e-5) and high == pytest.approx(5.155011, rel=1e-6)
    r = run_point(p, SolverSettings(method="rk4", t_end=2000.0, window=200.0, lyap=False))
    assert r.summary.regime == "sliding" and r.summary.drift == pytest.approx(high, rel=1e-5)


# -- the window's default and the engine's limits (core.solve) ----------------------------

def test_the_default_window_is_the_papers_or_half_a_shorter_run():
    assert SolverSettings().window == 1000.0
    assert SolverSettings(t_end=100).window == 50.0           # not refused: t_end alone is fine
    assert SolverSettings(t_end=2000).window == 1000.0
    with pytest.raises(ParameterError) as exc:                 # an explicit one still is
        SolverSettings(t_end=100, window=1000)
    assert exc.value.field == "window" and "t_end = 100" in str(exc.value)


@pytest.mark.parametrize(
    "kwargs,field",
    [(dict(trace_points=1), "trace_points"), (dict(trace_points=2.5), "trace_points"),
     (dict(trace_points=True), "trace_points"), (dict(trace_points=math.inf), "trace_points"),
     (dict(method=1), "method"), (dict(method=["euler"]), "method"),
     (dict(dt=True), "dt"), (dict(t_end=10**400), "t_end"), (dict(window=math.inf), "window")],
)
def test_more_bad_settings_name_their_field(kwargs, field):
    with pytest.raises(ParameterError) as exc:
        SolverSettings(**kwargs)
    assert exc.value.field == field


@pytest.mark.parametrize("value", [True, False, 10**400, "1e999", None, [1.0]])
def test_booleans_and_huge_integers_are_not_parameters(value):
    with pytest.raises(ParameterError) as exc:
        Params(k=value)
    assert exc.value.field == "k" and len(str(exc.value)) < 200


@pytest.mark.parametrize(
    "params,settings,field,allowed",
    [  # before: numba's "Int value is too large", a MemoryError, or 2**63 steps
        (dict(), dict(dt=1e-300), "dt", "dt >= 1e-05"),
        (dict(), dict(t_end=1e300), "t_end", "t_end <= 1e+07"),
        (dict(tau=1e9), dict(), "tau", "tau <= 1.342e+05"),
        (dict(), dict(dt=1e-12), "dt", "dt >= 1e-05"),
        (dict(tau=1e-300), dict(dt=1e-300), "dt", "dt >= 1e-05"),
        (dict(tau=0.0), dict(dt=1e-300, t_end=10, window=5), "dt", "dt >= 1e-09"),
        (dict(tau=1e6), dict(method="rk4"), "tau", "tau <= 6.711e+05"),  # rk4: 32 B a step
        (dict(tau=0.0), dict(dt=1.0, t_end=1e9), "t_end", "t_end <= 2.684e+08"),  # the logs
        (dict(), dict(trace_points=10**9), "trace_points", "trace_points <= "),
    ],
)
def test_runs_beyond_the_limits_are_refused_before_allocating(params, settings, field, allowed):
    with pytest.raises(LimitError) as exc:
        make_grid(Params(**params), SolverSettings(**settings))
    assert exc.value.field == field and allowed in str(exc.value)
    assert "per run" in str(exc.value)  # the cause


def test_what_a_run_needs_is_counted_part_by_part():
    s = SolverSettings()
    g = make_grid(Params(), s)                     # the paper's run: tau = 10 at dt = 1e-3
    m = memory_of(g, s)
    # the window at the end and the one that ends at the middle of the run
    assert m.ring == RING_BYTES["euler"] * 10_001 and m.window == SAMPLE_BYTES * 2 * 100_001
    assert m.logs == 8 * g.n_steps // g.renorm_steps and m.total < 10 * 2**20
    assert memory_of(g, SolverSettings(lyap=False)).logs == 0
    assert g.n_steps <= MAX_STEPS and m.total <= MAX_RUN_BYTES
    big = make_grid(Params(tau=1e5), s)            # the largest tau the limit lets through
    assert memory_of(big, s).total <= MAX_RUN_BYTES


@pytest.mark.parametrize(
    "settings,field",
    [(dict(t_end=10, window=1e-300), "window"),       # before: "sliding (at rest)" from 1 sample
     (dict(t_end=1e-300, window=1e-300), "t_end"),    # before: a run of 0 steps, "sliding"
     (dict(dt=9, t_end=10, window=5), "dt"),          # before: a traceback in core.classify
     (dict(t_end=1), "window")],
)
def test_a_run_to_classify_needs_a_window_of_enough_samples(settings, field):
    p = Params(tau=10.0)
    with pytest.raises(LimitError) as exc:
        validate_run(p, SolverSettings(**settings))
    assert exc.value.field == field and "60 samples" in str(exc.value)
    make_grid(p, SolverSettings(t_end=10, window=1e-300))   # integrating alone still may
