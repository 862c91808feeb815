"""Each figure's section says what the window shows and what is certified: one line per
panel counting the runs whose attractor was certified, by attractor, beside the measured
lines that describe the windows. The panels are built by hand: the counting is under test."""

from __future__ import annotations

from slopetui.reproduce.findings import Diagrams, fig7
from slopetui.reproduce.measures import certified_text
from slopetui.reproduce.report import section
from slopetui.sweeps.diagram import RunPoint, SweepDiagram
from tests.unit.test_findings_fig7 import diagrams


def _panel(runs: list[tuple[bool | None, str]]) -> SweepDiagram:
    from slopetui.sweeps.presets import BY_KEY
    from slopetui.sweeps.spec import parse_spec
    spec = parse_spec(BY_KEY["fig4a"].at_resolution(len(runs)))
    points = [RunPoint(i + 1, i, 0, float(i), None, "done", "oscillatory", [1.0], None,
                       attractor=attractor, certified=certified)
              for i, (certified, attractor) in enumerate(runs)]
    return SweepDiagram(1, "p", spec, points)


def test_the_count_names_each_certified_attractor_and_the_rest():
    text = certified_text(_panel([(True, "periodic"), (True, "periodic"),
                                  (True, "fixed-point"), (False, "periodic")]))
    assert text == ("certified attractors: 3 of 4 runs (75%): 2 periodic, 1 fixed-point; "
                    "the other 1 labels describe their window only")


def test_runs_computed_before_certification_say_so():
    text = certified_text(_panel([(None, "periodic"), (None, "fixed-point")]))
    assert "none of 2 runs was tried" in text and "describes its run's window" in text


def test_every_panel_of_a_section_gets_its_line():
    d: Diagrams = diagrams("fast-branch")
    out = section(fig7(d), d)
    assert out.count("certified attractors:") == 2
    assert "- Fig. 7A: certified attractors: none of 9 runs was tried" in out
