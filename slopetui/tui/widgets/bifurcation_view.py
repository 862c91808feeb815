"""The bifurcation diagram of a 1-D sweep, with a cursor that steps along the parameter.

The cursor is drawn on the plot, a vertical line at the chosen run's value
(slopetui.plots.bifurcation.CURSOR_MARKER, legible with colour off), and the title
names the run: the title alone left the eye to find the value on the axis.
"""

from __future__ import annotations

from textual.binding import Binding
from textual.reactive import reactive

from slopetui.display_text import terminal_safe
from slopetui.plots import render_sweep
from slopetui.sweeps.diagram import SweepDiagram
from slopetui.tui.messages import RunChosen, RunMarked
from slopetui.tui.widgets.plot_view import PlotView


class BifurcationView(PlotView, can_focus=True):
    """Left/right choose a run (a line at its value, and the title names it); enter opens
    it, m marks it for comparison."""

    BINDINGS = [
        Binding("left", "step(-1)", "←", show=False),
        Binding("right", "step(1)", "→", show=False),
        # out of the footer (which must keep ^q Quit at 80 columns): the title names the run
        Binding("enter", "choose", "Open run", id="bifurcation.open", show=False),
        Binding("m", "mark", "Mark", id="bifurcation.mark", show=False),
    ]

    index: reactive[int] = reactive(0)

    def __init__(self, *, id: str | None = None) -> None:
        super().__init__(id=id)
        self.diagram: SweepDiagram | None = None

    def set_diagram(self, diagram: SweepDiagram | None) -> None:
        if diagram is None or self.diagram is None or self.diagram.id != diagram.id:
            self.index = 0
        self.diagram = diagram
        self.show(None if diagram is None else self._draw_diagram)

    def _draw_diagram(self, width: int, height: int, color: bool) -> str:
        d = self.diagram
        assert d is not None
        x = d.spec.x
        run = d.runs[min(self.index, len(d.runs) - 1)]
        # the regime is stored text, and the plot is read back as ANSI (PlotView): escaped
        label = terminal_safe(run.regime or run.status)
        title = (f"{x.param} = {run.x:.5g}: {label} (run {run.id}) "
                 f"- {d.n_done}/{len(d.runs)} done")
        return render_sweep(d, width=width, height=height, color=color, title=title,
                            cursor=run.x)

    def action_step(self, delta: int) -> None:
        if self.diagram is not None and self.diagram.runs:
            self.index = min(max(self.index + delta, 0), len(self.diagram.runs) - 1)

    def watch_index(self) -> None:
        self.redraw()

    def action_choose(self) -> None:
        if self.diagram is not None and self.diagram.runs:
            self.post_message(RunChosen(self.diagram.runs[self.index].id))

    def action_mark(self) -> None:
        if self.diagram is not None and self.diagram.runs:
            self.post_message(RunMarked(self.diagram.runs[self.index].id))
