"""The paper's figures as presets, `slopetui reproduce`, and the report end to end."""

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


def test_the_report_runs_end_to_end(tmp_path, capsys):
    out = tmp_path / "docs" / "reproduction.md"
    code = main(["reproduce", "--report", "--resolution", "2", "--t-end", "100", "-j", "2",
                 "--out", str(out), "--db", f"sqlite:///{tmp_path / 's.db'}"])
    assert code == 0
    text = out.read_text()
    for figure in ("Fig. 2A", "Fig. 3", "Fig. 4A", "Fig. 4B", "Fig. 4C", "Fig. 5A", "Fig. 6B",
                   "Fig. 7A", "Fig. 8B", "Fig. 9A", "Fig. 10B"):
        assert figure in text
    assert text.count("**Verdict: ") == 11
    assert "**The paper says:**" in text and "```text" in text


@pytest.mark.parametrize("changes", [
    {"k": 4.0, "tau": 10.0}, {"k": 7.0, "tau": 10.0}, {"k": 12.0, "tau": 0.5},
    {"k": 40.0, "tau": 0.5}, {"a": 1.0, "k": 12.0, "tau": 3.0}, {"b": 24.8, "k": 12.0},
    {"c": 8.0, "k": 12.0, "tau": 1.0}, {"k": 0.0},
])
def test_the_fast_stability_test_matches_the_roots(changes):
    from core import Params
    from core.stability import leading_exponent
    from slopetui.reproduce.measures import linearly_stable

    p = Params(**changes)
    assert linearly_stable(p) == (leading_exponent(p) < 0)
