"""`slopetui continue --submit` and `slopetui branch` as a user types them: queue a
continuation, list it, read it back once a worker has computed it."""

from __future__ import annotations

import json

import pytest

from slopetui.cli import main
from slopetui.queue import branch_jobs
from slopetui.store.jobs import continuations
from tests.unit.test_branch_jobs import Never, inline

SUBMIT = ["continue", "--param", "k", "--from-hopf", "--tau", "2", "--points", "6", "--submit"]


def _compute(db) -> None:
    job = branch_jobs.claim(db, "w1")
    branch_jobs.compute(db, "w1", job, inline, Never(), max_attempts=3)


def test_submit_queues_and_branch_shows_it_queued_then_done(db, db_url, capsys):
    assert main([*SUBMIT, "--db", db_url, "--json"]) == 0
    assert json.loads(capsys.readouterr().out) == {"id": 1, "status": "queued"}
    assert continuations.continuation(db, 1).status == "queued"
    assert main(["branch", "--db", db_url]) == 0
    listed = capsys.readouterr().out.splitlines()
    assert listed[1].split()[:5] == ["1", "k", "hopf1", "tau=2", "queued"]
    _compute(db)
    assert main(["branch", "1", "--db", db_url, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["status"] == "done" and out["criticality"] == "subcritical"
    assert len(out["branch"]) == out["n_points"] == 6
    assert set(out["branch"][0]) == {"value", "period", "amplitude", "stable",
                                     "leading_multiplier"}
    assert out["hopf_value"] > out["branch"][-1]["value"]  # a subcritical branch bends back
    assert main(["branch", "1", "--db", db_url]) == 0
    text = capsys.readouterr().out
    assert "6 points" in text and "subcritical" in text and "end: 6 points computed" in text
    assert "in k from Hopf point 1: done" in text and "\nHopf point 1: k = " in text


# computes the continuation twice (~0.6 s): out of the fast loop, as the CLI's slowest test
@pytest.mark.slow
def test_the_foreground_and_the_stored_branch_print_the_same_points(db, db_url, capsys):
    assert main([*SUBMIT[:-1], "--json"]) == 0
    here = json.loads(capsys.readouterr().out)["branch"]
    assert main([*SUBMIT, "--db", db_url]) == 0
    _compute(db)
    capsys.readouterr()
    assert main(["branch", "1", "--db", db_url, "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["branch"] == here


def test_unknown_continuation_and_plot_without_id_are_usage_errors(db_url, capsys):
    assert main(["branch", "7", "--db", db_url]) == 2
    assert "no continuation 7" in capsys.readouterr().err
    assert main(["branch", "--plot", "--db", db_url]) == 2
    assert "give its ID" in capsys.readouterr().err
    assert main(["branch", "--db", db_url]) == 0
    assert "no continuations yet" in capsys.readouterr().out


def test_bad_input_to_submit_writes_nothing(db, db_url, capsys):
    assert main(["continue", "--param", "k", "--to", "-3", "--submit", "--db", db_url]) == 2
    assert "k = " in capsys.readouterr().err
    assert continuations.continuations(db) == []
