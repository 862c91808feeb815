"""The compare screen: the runs marked with m (in a diagram or a run's detail), their
m_y against time and their phase portraits overlaid, one colour and marker per run.

Like the run detail, the traces are recomputed, not stored (slopetui.sweeps.recompute):
one thread worker integrates the runs one after the other and says how far it got; a
run that cannot be recomputed (invalid inputs, a failed integration) is named in the
status line and left out of the plots. f writes the same comparison as a figure file
(``slopetui figure --run A --run B`` from the shell).
"""

from __future__ import annotations

from dataclasses import dataclass

from textual import work
from textual.app import ComposeResult
from textual.binding import Binding
from textual.message import Message
from textual.widgets import Header, Static, TabbedContent, TabPane
from textual.worker import get_current_worker

from slopetui.plots.compare_plots import Overlay, render_compare_phase, render_compare_time
from slopetui.sweeps.recompute import StoredRun, Traces, load_run, recompute
from slopetui.sweeps.run_labels import run_labels
from slopetui.tui.screens.base import SlopeScreen
from slopetui.tui.screens.run_detail import cause_of
from slopetui.tui.widgets.plot_view import PlotView
from slopetui.tui.widgets.steady_footer import SteadyFooter

TAB_TIME, TAB_PHASE = "compare-time", "compare-phase"


@dataclass
class CompareProgress(Message):
    text: str


@dataclass
class CompareReady(Message):
    runs: list[tuple[StoredRun, Traces]]
    failures: list[str]


class CompareScreen(SlopeScreen[None]):
    """Two or more runs overlaid (the app's marked runs when the screen opened)."""

    BINDINGS = [
        Binding("escape", "back", "Back", id="compare.back"),
        Binding("f", "figure", "Figure", id="compare.figure"),
        # the tabs are on screen and clickable: their keys stay out of the footer (80 columns)
        Binding("t", f"show_tab('{TAB_TIME}')", "Time", id="compare.tab_time", show=False),
        Binding("p", f"show_tab('{TAB_PHASE}')", "Phase", id="compare.tab_phase", show=False),
    ]

    def __init__(self, run_ids: list[int]) -> None:
        super().__init__()
        self.run_ids = list(run_ids)
        #: The recomputed runs, in the order marked (those that could not be: left out).
        self.computed: list[tuple[StoredRun, Traces]] = []

    def compose(self) -> ComposeResult:
        yield Header()
        yield Static(f"comparing runs {', '.join(map(str, self.run_ids))}", id="compare-runs",
                     markup=False)
        yield Static("", id="compare-status", markup=False)
        with TabbedContent(id="compare-tabs"):
            with TabPane("m_y against time", id=TAB_TIME):
                yield PlotView(id="compare-plot-time")
            with TabPane("Phase portraits", id=TAB_PHASE):
                yield PlotView(id="compare-plot-phase")
        yield SteadyFooter()

    def on_mount(self) -> None:
        self.sub_title = "compare runs"
        self.refresh_data()

    def refresh_data(self) -> None:
        if self.computed or self.db is None:
            return
        self._status(f"recomputing {len(self.run_ids)} runs…")
        self.query_one("#compare-tabs", TabbedContent).loading = True
        self.recompute()

    @work(thread=True, exclusive=True, group="compare")
    def recompute(self) -> None:
        db, worker = self.db, get_current_worker()
        if db is None:
            return
        computed: list[tuple[StoredRun, Traces]] = []
        failures: list[str] = []
        for i, run_id in enumerate(self.run_ids, 1):
            if worker.is_cancelled:  # the screen was closed: stop between two runs
                return
            self.post_message(CompareProgress(f"recomputing run {run_id} ({i} of {len(self.run_ids)})…"))
            try:
                run = load_run(db, run_id)
                if run is None:
                    failures.append(f"run {run_id}: not in this store")
                    continue
                computed.append((run, recompute(run)))
            except Exception as exc:  # one run's failure is named, the others still shown
                failures.append(f"run {run_id}: {cause_of(exc)}")
        self.post_message(CompareReady(computed, failures))

    def on_compare_progress(self, message: CompareProgress) -> None:
        self._status(message.text)

    def on_compare_ready(self, message: CompareReady) -> None:
        self.computed = message.runs
        self.query_one("#compare-tabs", TabbedContent).loading = False
        runs = [run for run, _ in message.runs]
        overlays = [Overlay(label, traces.t, traces.m_x, traces.m_y, traces.summary.frequency)
                    for label, (_, traces) in zip(run_labels(runs), message.runs, strict=True)]

        def time(w: int, h: int, c: bool) -> str:
            return render_compare_time(overlays, width=w, height=h, color=c)

        def phase(w: int, h: int, c: bool) -> str:
            return render_compare_phase(overlays, width=w, height=h, color=c)

        self.query_one("#compare-plot-time", PlotView).show(time)
        self.query_one("#compare-plot-phase", PlotView).show(phase)
        shown = f"{len(runs)} runs recomputed"
        if message.failures:
            self._status(f"{shown}; left out: {'; '.join(message.failures)}", "warning")
        else:
            self._status(shown + " (f writes the figure)", "ok")

    def action_back(self) -> None:
        self.dismiss(None)

    def action_show_tab(self, tab: str) -> None:
        self.query_one("#compare-tabs", TabbedContent).active = tab

    def action_figure(self) -> None:
        if len(self.computed) < 1:
            self.notify("the runs are not recomputed yet", severity="warning")
            return
        self.app.write_runs_figure(self.computed)

    def _status(self, text: str, kind: str = "") -> None:
        status = self.query_one("#compare-status", Static)
        status.set_classes(kind)
        status.update(text)
