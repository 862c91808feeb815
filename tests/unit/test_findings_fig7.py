"""Fig. 7's verdict weighs the paper's dynamics, not only its region (a verdict "agree"
once rested on the region alone): the paper says the unstable runs go to "numerical
infinity"; a runaway that rests on the bounded fast sliding branch contradicts that, so
the verdict is "partly" even where the regions match. The panels here are the presets'
own lattices with labels set by hand: the rule is under test, not the integration
(the runaway itself is tests/unit/test_stiff_solver.py's, against scipy's Radau)."""

from __future__ import annotations

from slopetui.reproduce.findings import Diagrams, fig7
from slopetui.sweeps.diagram import RunPoint, SweepDiagram
from slopetui.sweeps.presets import BY_KEY
from slopetui.sweeps.spec import parse_spec


def panel(key: str, attractor: str, small_tau_sliding: bool) -> SweepDiagram:
    """A 3 x 3 panel of the preset: every run unstable on ``attractor``, but (if asked) the
    smallest delay's row sliding at the fixed point."""
    spec = parse_spec(BY_KEY[key].at_resolution(3))
    runs, n = [], 0
    for iy, y in enumerate(spec.y.values()):
        for ix, x in enumerate(spec.x.values()):
            n += 1
            sliding = small_tau_sliding and iy == 0
            runs.append(RunPoint(n, ix, iy, float(x), float(y), "done",
                                 "sliding" if sliding else "unstable",
                                 [0.0] if sliding else [float("nan")], None,
                                 attractor="fixed-point" if sliding else attractor,
                                 drift=0.0 if sliding else float("nan")))
    return SweepDiagram(n, key, spec, runs)


def diagrams(attractor: str) -> Diagrams:
    d = Diagrams()
    d["fig7a"] = panel("fig7a", attractor, small_tau_sliding=True)    # delta = 1e-6
    d["fig7b"] = panel("fig7b", attractor, small_tau_sliding=False)   # delta = 0.1
    return d


def test_a_runaway_to_the_bounded_fast_branch_makes_the_verdict_partly():
    finding = fig7(diagrams("fast-branch"))
    assert finding.verdict == "partly"
    assert finding.reason.startswith("The region agrees with the paper; its dynamics do not")
    assert any("run away to the fast sliding branch: 15" in line for line in finding.measured)


def test_runs_that_diverge_as_the_paper_says_agree():
    finding = fig7(diagrams("divergent"))
    assert finding.verdict == "agree"
    assert not finding.reason.startswith("The region agrees")
