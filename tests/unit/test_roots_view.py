"""The run detail's list of the rest state's roots (slopetui.tui.widgets.roots_view): the
verdict and the leading nonzero root that decides it first, every root once (a pair with
its ±), each with the plot's marker, and no line wider than the list's column."""

from __future__ import annotations

import pytest

from core.params import Params
from core.rest_stability import RestRoot
from core.stability import hopf_k
from slopetui.sweeps.rest_roots import RestRoots, compute
from slopetui.tui.widgets.roots_view import LIST_WIDTH, root_text, roots_lines


def test_a_pair_is_shown_once_with_its_plus_minus_and_a_real_root_alone():
    assert root_text(complex(0.0080826, -1.809999)) == "+0.008083 ± 1.81i"
    assert root_text(complex(-3.456, 0.0)) == "-3.456"


@pytest.mark.parametrize(("k", "said", "sign"), [
    (4.0, "stable", "Re λ1 < 0"), (12.0, "unstable", "Re λ1 > 0")])
def test_the_verdict_and_its_root_come_first(k, said, sign):
    found = compute(Params(k=k, tau=2.0))  # the exact Hopf point at tau = 2: k = 9.13
    lines = roots_lines(found)
    assert lines[:3] == [f"sliding state: {said}", "by its leading nonzero root:", sign]
    assert lines[3] == f"o λ1 {root_text(found.roots[0].value)}  leading"
    assert [line[0] for line in lines[3:]] == \
        ["x" if r.factor == "variance" else "o" for r in found.roots]
    assert max(len(line) for line in lines) <= LIST_WIDTH


def test_on_the_axis_it_says_undecided_and_why():
    """At the closed-form Hopf point (d = 0) the leading root's real part is round-off."""
    p = Params(k=hopf_k(10.0, Params().F1), tau=10.0, d=0.0)
    lines = roots_lines(compute(p))
    assert lines[0] == "sliding state: undecided"
    assert lines[2] == "|Re λ1| <= 1e-10: unresolved" and len(lines[2]) <= LIST_WIDTH


def test_the_widest_root_fits_the_column():
    found = RestRoots(Params(), [RestRoot(complex(-0.0001234, 12.345), "delay")], 6, 0.0)
    assert roots_lines(found)[3] == "o λ1 -0.0001234 ± 12.345i  leading"
    assert len(roots_lines(found)[3]) == LIST_WIDTH
