"""`slopetui hysteresis --submit` and `--show` as a user types them: queue a sweep, read it
back queued, computed by a worker (inline here), and as the foreground command prints it;
`slopetui status` counts it."""

from __future__ import annotations

import json

import pytest

from slopetui.cli import main
from slopetui.store.jobs import hysteresis_sweeps
from tests.unit.test_hysteresis_jobs import _compute

SWEEP = ["hysteresis", "--param", "k", "--from", "8", "--to", "12", "--points", "4",
         "--tau", "2", "--t-settle", "300", "--window", "100"]


def test_submit_queues_and_show_prints_it_queued_then_done(db, db_url, capsys):
    assert main([*SWEEP, "--submit", "--db", db_url, "--json"]) == 0
    assert json.loads(capsys.readouterr().out) == {"id": 1, "status": "queued"}
    assert main(["status", "--db", db_url]) == 0
    assert "hysteresis sweeps: 1 queued" in capsys.readouterr().out
    assert main(["hysteresis", "--show", "1", "--db", db_url]) == 0
    text = capsys.readouterr().out
    assert "queued, 0 points" in text and "queued: 0 of 8 points so far" in text
    _compute(db, "w1")
    assert main(["hysteresis", "--show", "1", "--db", db_url, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["status"] == "done" and out["n_done"] == 8 and out["param"] == "k"
    assert [p["value"] for p in out["up"]] == [8.0, 8 + 4 / 3, 8 + 8 / 3, 12.0]
    assert set(out["up"][0]) == {"value", "regime", "amplitude", "detail", "growth", "jumped"}
    # refined inside the grid's bracket: the last point at rest, the first kicked off it
    assert (out["onset_up_before"], out["onset_up_after"]) == \
        (out["up"][0]["value"], out["up"][1]["value"])
    assert out["up"][0]["value"] < out["onset_up"] < out["up"][1]["value"]
    assert out["offset_down"] is None and out["offset_down_before"] is None
    assert out["tol"] == 1e-3
    assert main(["hysteresis", "--show", "1", "--plot", "--db", db_url]) == 0
    text = capsys.readouterr().out
    assert "up   k = 8 " in text and "kicked" in text
    assert f"up branch changes regime at k = {out['onset_up']:.6g} (refined to 0.001 relative; " \
        "bracket: last on the old attractor 8, first on the new 9.33333)" in text
    assert "down branch keeps its regime throughout" in text
    assert "m_y amplitude" in text and "up 4" in text and "down 4" in text


# computes the sweep twice (~0.6 s): out of the fast loop, as the CLI's slowest test
@pytest.mark.slow
def test_the_foreground_and_the_stored_sweep_print_the_same_points(db, db_url, capsys):
    assert main([*SWEEP, "--json"]) == 0
    here = json.loads(capsys.readouterr().out)
    assert main([*SWEEP, "--submit", "--db", db_url]) == 0
    assert "hysteresis sweep 1 queued" in capsys.readouterr().out
    _compute(db, "w1")
    assert main(["hysteresis", "--show", "1", "--db", db_url, "--json"]) == 0
    stored = json.loads(capsys.readouterr().out)
    for key in ("up", "down", "onset_up", "offset_down", "param", "dt", "t_settle", "window",
                "tol", "onset_up_before", "onset_up_after", "offset_down_before",
                "offset_down_after", "params", "solver", "engine"):
        assert stored[key] == here[key], key
    # and the lines: the foreground's point lines are the stored sweep's
    assert main(SWEEP) == 0
    lines = [s for s in capsys.readouterr().out.splitlines() if s.startswith(("up ", "down "))]
    assert main(["hysteresis", "--show", "1", "--db", db_url]) == 0
    shown = capsys.readouterr().out.splitlines()
    assert [s for s in shown if s.startswith(("up ", "down "))] == lines


def test_missing_flags_and_unknown_sweeps_are_usage_errors(db, db_url, capsys):
    assert main(["hysteresis", "--from", "8", "--to", "12"]) == 2
    assert "required: --param" in capsys.readouterr().err
    assert main(["hysteresis", "--param", "k", "--from", "8"]) == 2
    assert "required: --to" in capsys.readouterr().err
    assert main(["hysteresis", "--show", "3", "--db", db_url]) == 2
    assert "no hysteresis sweep 3" in capsys.readouterr().err
    assert main(["hysteresis", "--show", "3", "--submit", "--db", db_url]) == 2
    assert "not both" in capsys.readouterr().err
    assert main([*SWEEP[:-4], "--t-settle", "1", "--submit", "--db", db_url]) == 2
    assert "t-settle" in capsys.readouterr().err
    assert hysteresis_sweeps.hysteresis_sweeps(db) == []
