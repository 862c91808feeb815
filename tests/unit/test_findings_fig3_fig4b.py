"""Fig. 3's and Fig. 4B's text say what the paper's window shows and what the evidence
supports ('"torus, settled" at k = 20, tau >= 60 (Fig. 3) is not shown'; the
multi-slip states of Fig. 4B are long transients toward equally spaced n-slip orbits).
The panels are the presets' own lattices with labels set by hand: the sentences are under
test, not the integration (the classifier's rule is tests/unit/test_classify.py's)."""

from __future__ import annotations

import math
from types import SimpleNamespace

import pytest

from core.classify import Summary
from slopetui.reproduce import findings
from slopetui.reproduce.findings import Diagrams, fig3, fig4b
from slopetui.sweeps.diagram import RunPoint, SweepDiagram
from slopetui.sweeps.presets import BY_KEY
from slopetui.sweeps.spec import parse_spec


def fig3_panel(large_attractor: str) -> SweepDiagram:
    """The preset's tau = 20-100 at k = 20: periodic below tau = 60, from there maxima that
    never return, a band that stays, lambda_max within its errors of 0."""
    spec = parse_spec(BY_KEY["fig3"].at_resolution())
    runs = []
    for i, tau in enumerate(spec.x.values()):
        large = tau >= 60
        runs.append(RunPoint(i + 1, i, 0, float(tau), None, "done", "complex" if large else "oscillatory",
                             [1.0, 2.0], None, detail="no return" if large else "period-1",
                             period_count=-1 if large else 1, lambda_max=1e-5, lambda_err=4e-5,
                             attractor=large_attractor if large else "periodic", settled=True,
                             maxima_per_period=0 if large else 18))
    return SweepDiagram(1, "fig3", spec, runs)


@pytest.fixture
def no_echo_run(monkeypatch):
    """fig3 recomputes the conclusion's point (t_end = 1e5): a stand-in summary instead."""
    summary = Summary("oscillatory", "not departed", 5e-6, math.nan, 0,
                      attractor="unstable-fixed-point", flags=("not-departed",))
    monkeypatch.setattr(findings, "run_point", lambda p: SimpleNamespace(summary=summary))


def test_fig3_large_delays_are_undetermined_not_a_demonstrated_torus(no_echo_run):
    """Before: the text had no word on the large delays' attractor, and the runs' lines
    read "attractor torus, settled" with nothing against it."""
    d = Diagrams()
    d["fig3"] = fig3_panel("undetermined")
    f = fig3(d)
    assert "attractors at tau >= 60: undetermined 9" in f.measured
    assert ("At tau >= 60 the paper's window shows complex oscillations; in 9 of 9 runs their "
            "maxima do not return. The attractors the evidence supports there: undetermined 9 "
            "(of 9 runs). The 9 (undetermined 9) are not a demonstrated torus") in f.reason
    assert "18 -> 17 -> 18" in f.reason and "weak chaos, undetermined" in f.reason


def test_fig3_counts_a_returning_run_as_its_own_attractor(no_echo_run):
    """A periodic run at a large delay is shown, not listed among the unshown tori (the
    sentence said every window there never returns)."""
    d = Diagrams()
    d["fig3"] = fig3_panel("periodic")
    f = fig3(d)
    assert "in 0 of 9 runs their maxima do not return" in f.reason
    assert "not a demonstrated torus" not in f.reason


def test_fig3_says_which_tori_rest_on_exponents(no_echo_run):
    d = Diagrams()
    d["fig3"] = fig3_panel("torus")
    f = fig3(d)
    assert "9 torus and 0 chaotic rest on the exponents" in f.reason
    assert "not a demonstrated torus" not in f.reason


def test_fig4b_calls_the_multi_slip_states_long_transients():
    """Before: the text said the slips drift at t = 1e5, not where they are headed."""
    spec = parse_spec(BY_KEY["fig4b"].at_resolution())
    runs = [RunPoint(i + 1, i, 0, float(k), None, "done", "oscillatory", [2.0, 2.2], None,
                     detail="period-1, 2 maxima", period_count=1, attractor="periodic",
                     settled=False, maxima_per_period=2 if k < 20.5 else 3)
            for i, k in enumerate(spec.x.values())]
    d = Diagrams()
    d["fig4b"] = SweepDiagram(2, "fig4b", spec, runs)
    f = fig4b(d)
    assert f.verdict == "disagree"
    assert "with 2 or more maxima per period: 71 runs, 71 of them not settled at t = 1e5" in f.measured
    assert "are long transients" in f.reason
    assert "converge to equally spaced n-slip periodic orbits" in f.reason
    assert "2(n - 1) near-neutral exponents besides the flow's and no positive one" in f.reason
    assert "issue 35, 'The whole bifurcation picture'" in f.reason
