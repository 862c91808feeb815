"""The checks the CLI and the application's analysis forms share (slopetui.sweeps:
orbit_point, continuation_request, hysteresis_request, certified_rerun): each refusal
names its field, and the constants copied to keep numpy out of the faces' imports are
the engine's."""

from __future__ import annotations

import pytest

from core.params import ParameterError, Params
from slopetui.store.queries import runs_matching
from slopetui.sweeps import certified_rerun, continuation_request, hysteresis_request, orbit_point
from slopetui.sweeps.spec import SpecError
from tests.support import submit_quick


def test_the_copied_constants_are_the_engines():
    import core.hysteresis
    import core.periodic_orbit
    assert orbit_point.SEED_SPAN == core.periodic_orbit.SEED_SPAN
    assert continuation_request.SEED_T_END == core.periodic_orbit.SEED_T_END
    assert hysteresis_request.hysteresis_spec(Params(), 0.01, "k", "5", "6", "3").tol == \
        core.hysteresis.TOL


@pytest.mark.parametrize(("values", "field"), [
    ({"dt": "0"}, "dt"), ({"dt": "x"}, "dt"), ({"dt": "0.01", "tau": "-1"}, "tau"),
    ({"dt": "0.01", "k": ""}, "k")])
def test_a_bad_point_names_its_field(values, field):
    with pytest.raises(ParameterError) as caught:
        orbit_point.point_of(values)
    assert caught.value.field == field


@pytest.mark.parametrize(("args", "field"), [
    (("k", True, None, "1", "0.5"), "points"), (("k", True, None, "300", "0"), "max-step"),
    (("k", False, "10", "300", "0.5"), "to"), (("delta", True, None, "300", "0.5"), "param"),
    (("k", True, "nan", "300", "0.5"), "to")])
def test_a_bad_continuation_names_its_field(args, field):
    with pytest.raises(ParameterError) as caught:
        continuation_request.continuation_spec(Params(k=10.0), 0.01, *args)
    assert caught.value.field == field


def test_a_continuation_is_built_as_asked():
    spec = continuation_request.continuation_spec(Params(k=10.0), 0.01, "k", True, "12", "50",
                                                  "0.25")
    assert (spec.name, spec.from_hopf, spec.end, spec.max_points, spec.max_step) == \
        ("k", True, 12.0, 50, 0.25)


@pytest.mark.parametrize(("args", "field"), [
    (("k", "5", "5", "3"), "to"), (("k", "5", "6", "1"), "points"),
    (("k", "-1", "6", "3"), "k"), (("k", "5", "6", "3", "1"), "t-settle"),
    (("k", "5", "6", "3", None, "1e9"), "window"), (("k", "5", "6", "3", None, None, "0.9"), "tol")])
def test_a_bad_hysteresis_sweep_names_its_field(args, field):
    with pytest.raises(ParameterError) as caught:
        hysteresis_request.hysteresis_spec(Params(), 0.01, *args)
    assert caught.value.field == field


def test_a_certified_rerun_is_the_run_again_with_the_certified_stop(db):
    submit_quick(db, 2, stop="t_end")
    run = runs_matching(db, sweep=1)[1]
    out = certified_rerun.rerun_certified(db, run.id)
    (again,) = runs_matching(db, sweep=out.sweep_id)
    assert again.stop == "certified" and run.stop == "t_end"
    for name in ("a", "b", "c", "d", "k", "v", "tau", "delta", "method", "dt", "t_end",
                 "window", "lyap", "history"):
        assert getattr(again, name) == getattr(run, name), name


def test_a_certified_rerun_of_no_run_names_the_run(db):
    with pytest.raises(SpecError) as caught:
        certified_rerun.rerun_spec(db, 99)
    assert caught.value.field == "run"
