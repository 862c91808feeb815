"""Every result names what it was computed at (slopetui.provenance): the JSON of each
computation (params, solver, engine), the columns of a sweep's export (engine_version,
engine_digest), as the user types the commands."""

from __future__ import annotations

import csv
import io
import json

import pandas as pd
import pytest
from sqlalchemy import update

import slopetui
from core.jit_cache import source_digest
from core.params import PARAM_NAMES, Params
from slopetui.cli import main
from slopetui.provenance import caption, computed_at
from slopetui.store.models import Run
from tests.support import finish_all, submit_quick

THIS_ENGINE = {"version": slopetui.__version__, "digest": source_digest()}
QUICK = ["--tau", "2", "--method", "rk4", "--dt", "0.01", "--t-end", "200", "--window", "100"]


def _printed(capsys, args: list[str]) -> dict:
    assert main(args) == 0
    return json.loads(capsys.readouterr().out)


def test_run_json_names_its_params_solver_and_engine(capsys):
    out = _printed(capsys, ["run", "--k", "10", "--delta", "0.2", *QUICK, "--no-lyap", "--json"])
    assert out["params"] == {"a": 3.2, "b": 7.2, "c": 4.8, "d": 1e-4, "k": 10.0, "v": 0.1,
                             "tau": 2.0, "delta": 0.2}
    assert out["solver"] == {"method": "rk4", "dt": 0.01, "t_end": 200.0, "window": 100.0,
                             "lyap": False, "history": "constant", "stop": "t_end"}
    assert out["engine"] == THIS_ENGINE


def test_orbit_json_names_its_solver_and_engine(capsys):
    out = _printed(capsys, ["orbit", "--k", "10", "--tau", "10", "--json"])
    assert list(out["params"]) == list(PARAM_NAMES) and out["params"]["tau"] == 10.0
    assert out["solver"] == {"method": "rk4", "dt": out["dt"], "t_seed": 3000.0}
    assert out["engine"] == THIS_ENGINE


def test_continue_and_its_stored_branch_name_the_same_inputs(db, db_url, capsys):
    from tests.unit.test_cli_branch import SUBMIT, _compute

    here = _printed(capsys, [*SUBMIT[:-1], "--json"])
    assert here["params"]["tau"] == 2.0 and here["engine"] == THIS_ENGINE
    assert here["solver"] == {"method": "rk4", "dt": here["dt"], "from_hopf": True,
                              "points": 6, "max_step": 0.5}
    assert main([*SUBMIT, "--db", db_url]) == 0
    _compute(db)
    capsys.readouterr()
    stored = _printed(capsys, ["branch", "1", "--db", db_url, "--json"])
    for key in ("params", "solver", "engine"):
        assert stored[key] == here[key], key
    # the followed parameter is the branch's start, the Hopf point, not the value typed
    assert here["params"]["k"] == here["hopf"]["value"] == stored["hopf_value"]
    assert here["params"]["k"] != Params().k  # the k typed (the default: no --k)


def test_a_stored_branch_from_hopf_with_no_point_yet_names_no_start(db, db_url, capsys):
    from tests.unit.test_cli_branch import SUBMIT

    assert main([*SUBMIT, "--db", db_url]) == 0
    capsys.readouterr()
    stored = _printed(capsys, ["branch", "1", "--db", db_url, "--json"])
    assert stored["params"]["k"] is None and stored["params"]["tau"] == 2.0


def test_hysteresis_and_its_stored_sweep_name_the_same_inputs(db, db_url, capsys):
    from tests.unit.test_cli_hysteresis import SWEEP
    from tests.unit.test_hysteresis_jobs import _compute

    assert main([*SWEEP, "--submit", "--db", db_url]) == 0
    _compute(db, "w1")
    capsys.readouterr()
    stored = _printed(capsys, ["hysteresis", "--show", "1", "--db", db_url, "--json"])
    # the sweep's start: the parameter it follows at --from, the others as given
    assert stored["params"]["k"] == 8.0 and stored["params"]["tau"] == 2.0
    assert stored["solver"] == {"method": "rk4", "dt": 0.01, "t_settle": 300.0,
                                "window": 100.0, "tol": 1e-3}
    assert stored["engine"] == THIS_ENGINE


@pytest.mark.parametrize("stored_engine, version", [(None, slopetui.__version__),
                                                    ("0123456789abcdef", "")])
def test_export_names_each_runs_engine(db, db_url, capsys, stored_engine, version):
    """The digest the run was computed with, and the version only where it is known: the
    store keeps no version, so another engine's is not guessed (an empty cell, null)."""
    sweep = submit_quick(db, 2).sweep_id
    finish_all(db)
    if stored_engine is not None:
        with db.sessions() as s, s.begin():
            s.execute(update(Run).values(engine=stored_engine))
    digest = stored_engine or source_digest()
    assert main(["export", str(sweep), "--csv", "--db", db_url]) == 0
    table = list(csv.DictReader(io.StringIO(capsys.readouterr().out)))
    assert [(r["engine_version"], r["engine_digest"]) for r in table] == [(version, digest)] * 2
    assert main(["export", str(sweep), "--json", "--db", db_url]) == 0
    rows = json.loads(capsys.readouterr().out)
    assert [(r["engine_version"], r["engine_digest"]) for r in rows] == [(version or None, digest)] * 2
    frame = slopetui.Store(db).runs(sweep)
    assert frame["engine_digest"].tolist() == [digest] * 2
    assert frame["engine_version"].isna().all() if not version else \
        frame["engine_version"].tolist() == [version] * 2
    assert isinstance(frame, pd.DataFrame)


def test_a_caption_is_one_line_of_the_same_facts():
    from core.params import Params

    facts = computed_at(Params(k=10), {"method": "rk4", "dt": 0.01, "t_end": 200.0,
                                       "history": "constant", "window": None})
    line = caption(facts, varied=("k",))
    assert "\n" not in line
    assert line.startswith("a=3.2 b=7.2 c=4.8 d=0.0001 k varied v=0.1 tau=10 delta=0.1; rk4, ")
    assert "dt=0.01, t_end=200, history=constant;" in line and "window" not in line
    assert line.endswith(f"; slopetui {slopetui.__version__}, engine {source_digest()}")


def test_run_json_names_a_carried_history_as_export_does(db, db_url, capsys):
    """`run --history run:ID --json`: ``history`` is the carried state's name, as the
    store keeps it and `export` writes it (and as ``solver.history``); what was typed is
    ``history_given``."""
    from slopetui.sweeps.carried import final_state_of

    submit_quick(db, 2, tau=2.0, lyap=False)
    finish_all(db)
    out = _printed(capsys, ["run", "--k", "10", "--history", "run:1", *QUICK, "--no-lyap",
                            "--json", "--db", db_url])
    name = final_state_of(db, 1).name
    assert name.startswith("state:")
    assert out["history"] == out["solver"]["history"] == name
    assert out["history_given"] == "run:1"
    plain = _printed(capsys, ["run", "--k", "10", *QUICK, "--no-lyap", "--json"])
    assert plain["history"] == "constant" and "history_given" not in plain
