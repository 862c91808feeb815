"""The same run gives the same JSON values from `slopetui run --json` and, stored through
the queue (submitted, computed by a real `slopetui worker`), from `slopetui export --json`:
its result key by key, what it was computed at (params, solver, engine), and one spelling
of a value that does not exist (null: the period of a sliding run)."""

from __future__ import annotations

import json
import math

from core.result_fields import JSON_KEYS
from tests.support import slopetui_cli

#: Two points of one sweep over k at tau = 2: k = 4 slides (its period does not exist),
#: k = 10 oscillates (a certified orbit: multipliers and all).
SPEC = """
name = "same run, same JSON"
[x]
param = "k"
start = 4
stop = 10
num = 2
[fixed]
tau = 2
[solver]
method = "rk4"
dt = 0.01
t_end = 200
window = 100
lyap = true
stop = "t_end"
"""
SOLVER_FLAGS = ["--tau", "2", "--method", "rk4", "--dt", "0.01", "--t-end", "200",
                "--window", "100", "--stop", "t_end"]
#: Wall time: the one key whose value is not the run's.
NOT_THE_RUN = {"runtime_s"}


def _json(*args: str) -> object:
    done = slopetui_cli(*args)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout, parse_constant=lambda name: AssertionError(name))


def test_run_json_and_export_json_give_the_same_values(tmp_path):
    db = f"sqlite:///{tmp_path / 'store.db'}"
    spec = tmp_path / "spec.toml"
    spec.write_text(SPEC, encoding="utf-8")
    assert slopetui_cli("submit", str(spec), "--db", db).returncode == 0
    worker = slopetui_cli("worker", "-j", "1", "--exit-when-idle", "--db", db,
                          "--log", str(tmp_path / "worker.log"))
    assert worker.returncode == 0, worker.stderr
    rows = _json("export", "1", "--json", "--db", db)
    assert isinstance(rows, list) and [r["status"] for r in rows] == ["done", "done"]
    for row in rows:
        here = _json("run", "--k", repr(row["k"]), *SOLVER_FLAGS, "--json")
        assert isinstance(here, dict)
        for key in JSON_KEYS:
            if key not in NOT_THE_RUN:
                assert here[key] == row[key], (row["k"], key, here[key], row[key])
        assert here["history"] == row["history"] == "constant"
        assert all(here["params"][n] == row[n] for n in here["params"])
        assert all(here["solver"][s] == row[s] for s in here["solver"])
        assert here["engine"] == {"version": row["engine_version"],
                                  "digest": row["engine_digest"]}
    sliding, oscillating = rows
    assert sliding["regime"] == "sliding" and sliding["period"] is None
    assert oscillating["regime"] == "oscillatory" and math.isfinite(oscillating["period"])


#: A sweep carried on from run 2 (k = 10 of SPEC): every point starts from its final state.
CARRIED = SPEC.replace('name = "same run, same JSON"', 'name = "carried on"').replace(
    "start = 4", "start = 10").replace("stop = 10", "stop = 12") + '[[initial]]\nhistory = "run:2"\n'


def test_a_carried_history_is_named_alike_by_run_json_and_export_json(tmp_path):
    db = f"sqlite:///{tmp_path / 'store.db'}"
    for i, text in enumerate([SPEC, CARRIED]):
        spec = tmp_path / f"spec{i}.toml"
        spec.write_text(text, encoding="utf-8")
        submitted = slopetui_cli("submit", str(spec), "--db", db)
        assert submitted.returncode == 0, submitted.stderr
        worker = slopetui_cli("worker", "-j", "1", "--exit-when-idle", "--db", db,
                              "--log", str(tmp_path / "worker.log"))
        assert worker.returncode == 0, worker.stderr
    rows = _json("export", "2", "--json", "--db", db)
    assert isinstance(rows, list)
    row = next(r for r in rows if r["k"] == 10.0)
    assert row["status"] == "done" and row["history"].startswith("state:")
    here = _json("run", "--k", "10", *SOLVER_FLAGS, "--history", "run:2", "--json", "--db", db)
    assert isinstance(here, dict)
    assert here["history"] == here["solver"]["history"] == row["history"]
    assert here["history_given"] == "run:2"
    for key in JSON_KEYS:
        if key not in NOT_THE_RUN:
            assert here[key] == row[key], (key, here[key], row[key])
