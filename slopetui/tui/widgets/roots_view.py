"""The run detail's Roots tab: the rest (sliding) state's rightmost characteristic roots at
the run's point, listed beside their plot in the complex plane (slopetui.plots.root_plot:
Re against Im, the imaginary axis marked).

The list's first lines name the leading nonzero root as what decides the rest state's
stability, and say which way it decides; the roots follow, best first, one a line, each
with the plot's marker (o: the delay factor's, x: the variance block's), a complex pair
once with its ±. At 80 x 24 the tab's body is 12 lines: two for the verdict and the nine
roots (`slopetui roots`' default six of the delay factor and at most three of the
variance block) fit it whole; a list that does not fit scrolls. The numbers are
computed by the screen's thread worker (slopetui.sweeps.rest_roots.compute); this
widget only draws them.
"""

from __future__ import annotations

from textual.app import ComposeResult
from textual.containers import Horizontal, VerticalScroll
from textual.widgets import Static

from core.rest_stability import NEUTRAL_TOL
from slopetui.plots.root_plot import STABLE, VARIANCE, render_roots
from slopetui.sweeps.rest_roots import RestRoots
from slopetui.tui.widgets.plot_view import PlotView

#: What decided the verdict, by verdict: which side of the imaginary axis λ1 lies on.
DECIDED_BY = {"stable": "Re λ1 < 0", "unstable": "Re λ1 > 0",
              "undecided": f"|Re λ1| <= {NEUTRAL_TOL:g}: unresolved"}
#: The list's columns (its padding excluded): its longest line, a root with its marker,
#: index, both parts and "leading" ("o λ1 -0.0001234 ± 12.345i  leading": 34); the
#: plot beside it keeps 44 of 80 columns, which its legend fills in two lines.
LIST_WIDTH = 34


def root_text(value: complex) -> str:
    """A root as "+0.008083 ± 1.8100i" (a pair, once) or "-3.456" (real)."""
    re = format(value.real, "+.4g")
    return re if value.imag == 0.0 else f"{re} ± {abs(value.imag):.5g}i"


def roots_lines(found: RestRoots) -> list[str]:
    """The list: the verdict and what decides it (the leading nonzero root), then every
    root, best first, with the plot's marker; the leading one says so. At most LIST_WIDTH
    columns a line."""
    lines = [f"sliding state: {found.stability}", "by its leading nonzero root:",
             f"{DECIDED_BY[found.stability]}"]
    for i, root in enumerate(found.roots, 1):
        marker = VARIANCE[0] if root.factor == "variance" else STABLE[0]
        lines.append(f"{marker} λ{i} {root_text(root.value)}" + ("  leading" if i == 1 else ""))
    return lines


class RootsView(Horizontal):
    """The list of the roots (scrolled if it does not fit) and their plot beside it."""

    DEFAULT_CSS = """
    RootsView { height: 1fr; }
    RootsView #roots-list { width: 36; height: 1fr; padding: 0 1; }
    RootsView #plot-roots { width: 1fr; }
    """

    def compose(self) -> ComposeResult:
        with VerticalScroll(id="roots-list"):
            yield Static("", id="roots-text", markup=False)
        yield PlotView(id="plot-roots")

    def say(self, text: str) -> None:
        """No roots to show (yet): ``text`` says why, and the plot is blank."""
        self.query_one("#roots-text", Static).update(text)
        self.query_one("#plot-roots", PlotView).show(None)

    def show(self, found: RestRoots) -> None:
        """Draw ``found``: its list and its plot."""
        self.query_one("#roots-text", Static).update("\n".join(roots_lines(found)))
        pairs = [(r.value, r.factor) for r in found.roots]
        # no title: the list beside it says what it shows, and at 80 x 24 the plot's 12
        # lines hold its canvas (10 at least) and its legend's two lines, no more
        self.query_one("#plot-roots", PlotView).show(
            lambda width, height, color: render_roots(pairs, width=width, height=height,
                                                      color=color))
