"""The paper's figures as presets, `slopetui reproduce`, and an interrupted report (the report
end to end, with a real pool: tests/integration/test_report.py)."""

from __future__ import annotations

import pytest

from slopetui.cli import main
from slopetui.sweeps.presets import BY_KEY, PRESETS
from slopetui.sweeps.spec import parse_spec

PANELS = {"fig2a", "fig2b", "fig2c", "fig2d", "fig3", "fig4a", "fig4b", "fig4c",
          *(f"fig{n}{p}" for n in range(5, 11) for p in "ab")}


def test_there_is_a_preset_for_every_panel():
    assert set(BY_KEY) == PANELS


@pytest.mark.parametrize("preset", PRESETS, ids=lambda p: p.key)
def test_every_preset_builds_a_valid_sweep(preset):
    full = parse_spec(preset.spec)
    small = parse_spec(preset.at_resolution(3, t_end=100.0))
    assert full.solver.method == "euler" and full.solver.dt == 1e-3 and full.solver.t_end == 1e5
    assert small.solver.t_end == 100.0 and small.solver.window <= 50.0
    assert small.n_runs <= full.n_runs and small.n_runs in (1, 3, 9, 12)
    assert preset.claim and preset.note and preset.figure.startswith("Fig. ")


def test_list_and_queue(tmp_path, capsys):
    assert main(["reproduce", "--list"]) == 0
    out = capsys.readouterr().out
    assert all(key in out for key in PANELS)
    url = f"sqlite:///{tmp_path / 's.db'}"
    assert main(["reproduce", "fig5a", "--resolution", "4", "--t-end", "100", "--db", url]) == 0
    assert "fig5a: sweep 1, 16 runs queued" in capsys.readouterr().out


@pytest.mark.parametrize("args, message", [
    (["fig99"], "FIG: unknown figure 'fig99'"),
    (["fig5a", "--resolution", "1"], "--resolution must be in 2..500"),
    (["all"], "add --yes"),
])
def test_bad_reproduce_input(tmp_path, capsys, args, message):
    code = main(["reproduce", *args, "--db", f"sqlite:///{tmp_path / 's.db'}"])
    assert code == 2 and message in capsys.readouterr().err


@pytest.mark.parametrize("changes", [
    {"k": 4.0, "tau": 10.0}, {"k": 7.0, "tau": 10.0}, {"k": 12.0, "tau": 0.5},
    {"k": 40.0, "tau": 0.5}, {"a": 1.0, "k": 12.0, "tau": 3.0}, {"b": 24.8, "k": 12.0},
    {"c": 8.0, "k": 12.0, "tau": 1.0}, {"k": 0.0},
])
def test_the_fast_stability_test_matches_the_roots(changes):
    from core.params import Params
    from core.stability import leading_exponent
    from slopetui.reproduce.measures import linearly_stable

    p = Params(**changes)
    assert linearly_stable(p) == (leading_exponent(p) < 0)


def test_an_interrupted_report_draws_no_verdict_from_missing_runs(tmp_path, capsys,
                                                                  monkeypatch):
    """Ctrl-C after a few hundred runs once wrote "5381 runs" and DISAGREE verdicts for
    figures that had no runs at all ("nan% of 0 runs agree")."""
    from slopetui.reproduce import report
    from slopetui.store.models import Run, Sweep
    from slopetui.store.open import open_store
    from tests.support import finish_all

    url = f"sqlite:///{tmp_path / 's.db'}"

    def interrupted_pool(opts, n_workers):  # the pool stopped after the Fig. 2 points
        db = open_store(url)
        with db.transaction() as s:
            for sweep in s.query(Sweep).filter(~Sweep.name.like("Fig. 2%")):
                sweep.status = "paused"
        finish_all(db)
        return 0

    monkeypatch.setattr(report, "run_pool", interrupted_pool)
    out = tmp_path / "reproduction.md"
    code = main(["reproduce", "--report", "--resolution", "2", "--t-end", "100",
                 "--out", str(out), "--db", url])
    assert code == 1 and "INCOMPLETE" in capsys.readouterr().out
    text = out.read_text()
    assert text.startswith("# The paper reproduced (INCOMPLETE)")
    assert "nan" not in text.lower()
    assert text.count("**Verdict: ") == 1  # Fig. 2 only: every other finding lacks runs
    with open_store(url).sessions() as s:
        n_done = s.query(Run).filter(Run.status == "done").count()
        n_all = s.query(Run).count()
    assert f"{n_done} of {n_all} runs done" in text
