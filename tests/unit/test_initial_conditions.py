"""Sweeps over initial conditions (spec [[initial]], `submit --initial`): each lattice
point is computed once per condition, the phase diagram shows per cell the common regime
or "depends", a history is recorded on every run and keys the cache, and a stored run's
final state can start a sweep's runs."""

from __future__ import annotations

import json

import pytest

from core.regimes import DEPENDS
from slopetui.cli import main
from slopetui.plots.sweep_diagram import render_sweep
from slopetui.store.queries import run_by_id
from slopetui.sweeps.diagram import load_diagram
from slopetui.sweeps.initial_dependence import condition_notes, drawn
from slopetui.sweeps.spec import SpecError, parse_spec
from slopetui.sweeps.submit import submit
from tests.support import finish_all

#: k below and inside the bistable band at tau = 10 (fold of cycles 1.214, Hopf 6.15):
#: below it every start rests; inside it delta = 1e-6 rests and delta = 2 reaches the
#: cycle (RK4, t = 2000: the report's checks at k = 3 and 5).
PLANE = {"x": {"param": "k", "start": 0.5, "stop": 5.0, "num": 3},
         "y": {"param": "tau", "start": 10.0, "stop": 10.0, "num": 1},
         "solver": {"method": "rk4", "dt": 0.01, "t_end": 2000.0, "window": 500.0, "lyap": False},
         "initial": [{"delta": 1e-6}, {"delta": 2.0}]}


def test_every_point_once_per_condition_and_the_map(db):
    out = submit(db, parse_spec(PLANE, submitting=True))
    assert out.n_runs == 6
    finish_all(db)
    d = load_diagram(db, out.sweep_id)
    assert sorted((r.ic, r.delta) for r in d.runs) == [(0, 1e-6)] * 3 + [(1, 2.0)] * 3
    verdicts = {r.x: r.regime for r in drawn(d).runs}
    assert verdicts == {0.5: "sliding", 2.75: DEPENDS, 5.0: DEPENDS}
    notes = condition_notes(d)
    assert notes[(1, 0)] == "delta 1e-06: sliding, delta 2: oscillatory"
    text = render_sweep(d, width=80, height=20, color=False)
    assert "depends" in text and "#" in text


def test_the_history_is_on_every_run_and_in_its_cache_key(db):
    spec = {**PLANE, "initial": [{"delta": 0.1}, {"delta": 0.1, "history": "consistent"}]}
    out = submit(db, parse_spec(spec, submitting=True))
    finish_all(db)
    runs = [run_by_id(db, i) for i in range(1, out.n_runs + 1)]
    assert [r.history for r in runs] == ["constant"] * 3 + ["consistent"] * 3
    assert len({r.cache_key for r in runs}) == 6  # no condition took another's result


def test_a_stored_runs_final_state_starts_a_sweep(db, db_url, capsys):
    """history = run:ID: the run is recomputed, its state kept under its name, and every
    run of the sweep starts from it (same tau and step); another tau is refused."""
    first = submit(db, parse_spec({**PLANE, "initial": [{"delta": 2.0}]}, submitting=True))
    finish_all(db)
    source = 3  # k = 5, oscillating (from delta = 2)
    spec = {**PLANE, "initial": [{"delta": 1e-6}, {"history": f"run:{source}"}]}
    out = submit(db, parse_spec(spec, submitting=True))
    finish_all(db)
    d = load_diagram(db, out.sweep_id)
    warm = [r for r in d.runs if r.ic == 1]
    assert all(r.history.startswith("state:") for r in warm)
    # from the oscillating state, k = 2.75 and 5 (in the band) stay on the cycle; k = 0.5,
    # below the fold, has no cycle to stay on
    assert [r.regime for r in warm] == ["sliding", "oscillatory", "oscillatory"]
    assert first.sweep_id != out.sweep_id
    bad = {**PLANE, "y": {"param": "tau", "start": 5.0, "stop": 5.0, "num": 1},
           "initial": [{"history": f"run:{source}"}]}
    with pytest.raises(SpecError, match=r"initial\[0\]\.history.*tau = 10"):
        submit(db, parse_spec(bad, submitting=True))


def test_submit_flags_and_bad_conditions(db_url, capsys):
    assert main(["submit", "--x", "k=0.5:5:3", "--tau", "10", "--method", "rk4", "--dt", "0.01",
                 "--t-end", "200", "--no-lyap", "--initial", "delta=1e-6",
                 "--initial", "delta=0.1,history=consistent", "--db", db_url, "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["n_runs"] == 6
    for flags, field in ((["--initial", "delta"], "initial[0]"),
                         (["--initial", "delta=-x"], "initial[0].delta"),
                         (["--initial", "history=sideways"], "initial[0].history"),
                         (["--initial", "delta=1", "--initial", "delta=1"], "initial"),
                         (["--history", "kinked"], "solver.history")):
        assert main(["submit", "--x", "k=3:7:3", "--tau", "10", *flags, "--db", db_url]) == 2
        assert field in capsys.readouterr().err


def test_conditions_and_adaptive_refinement_do_not_mix():
    spec = {**PLANE, "x": {"param": "k", "start": 1, "stop": 9, "num": 9},
            "y": {"param": "tau", "start": 1, "stop": 9, "num": 9}, "adaptive": {"levels": 2}}
    with pytest.raises(SpecError, match="adaptive"):
        parse_spec(spec)
    assert parse_spec({**spec, "initial": [{"delta": 0.5}]}).n_runs == 81
    assert parse_spec(PLANE).to_dict()["initial"] == PLANE["initial"]
