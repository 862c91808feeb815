"""The run detail screen: one run's parameters and stored summary, and four plots of its
traces (m_x and m_y against time over the analysis window, the phase portrait, the power
spectrum of m_y, the running lambda_max estimate converging); its certificate; and the
rest state's characteristic roots at its point (the Roots tab, key e: computed in a
thread worker the first time the tab is shown, drawn by slopetui.tui.widgets.roots_view).

**The traces are recomputed on demand, not stored.** The model is deterministic: the
run's parameters and solver settings integrated again give the trajectory the worker
saw (bit for bit with the same engine on the same machine). Storing it would cost
~4 MB per run (a 1000-unit window is 1e5 samples of 5 variables) for a plot that is
looked at for a few runs of a sweep; the store keeps the summaries only. Opening a
finished run recomputes it in a thread worker (as long as the worker took, usually
well under a second at RK4), then compares the recomputed regime and lambda_max with
the stored ones, and says when they differ and whether the engine changed since. The
copy of the run, its recomputation and the tolerance policy are UI-free, in
``slopetui.sweeps.recompute``; the result lines of the header list the fields of
``core.result_fields`` marked ``detail``.

At 80 x 24 the whole header shows, every stored result field included: its result items
are packed into lines as wide as the screen (``summary_text``), the note on where the
plots come from is the header's subtitle, the tabs take one line, and a λmax note too long
for one line is wrapped under the plot, not cut. A header taller than the room the plot
leaves it (a long certificate, say) scrolls the screen rather than hiding a line.

The time series shows the last TIME_PERIODS periods of the run's dominant frequency
(a window holds hundreds: drawn whole it is a solid wall of braille); z zooms out to
50 periods, then to the whole window, then back (a fixed point has no period and is
always shown whole). The footer shows the screen's own keys only (back, recompute,
zoom, figure, mark): the tab keys t, p, s, l, c, e are hidden there, as the tabs are on
screen and clickable, and the help lists them.

Runs that are not done (queued, running, failed, cancelled) show their status and
stored error; their traces are computed only on request (r), and only when their
inputs are valid. So are the *inferred* runs of an adaptive sweep: the screen says that
their regime was inferred from their cell's corners, not computed, and r computes them
(and compares the computed regime with the inferred one). Every database call and computation
runs in a thread worker and reports back with a message; widgets are touched on the UI thread only.
"""

from __future__ import annotations

import math
import textwrap
from collections.abc import Sequence
from dataclasses import dataclass

from textual import events, work
from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import VerticalScroll
from textual.message import Message
from textual.widgets import Header, Static, TabbedContent, TabPane
from textual.worker import get_current_worker

from core.jit_cache import source_digest
from core.params import PARAM_NAMES, ParameterError, Params
from core.result_fields import DETAIL_FIELDS, ResultField
from core.solve import SolverSettings
from slopetui.display_text import terminal_safe_lines
from slopetui.plots.multiplier_plot import render_multipliers
from slopetui.plots.run_plots import (
    TIME_PERIODS,
    render_lyapunov,
    render_phase_portrait,
    render_spectrum,
    render_time_series,
)
from slopetui.sweeps import rest_roots
from slopetui.sweeps.recompute import (
    MATCH_TEXT,
    StoredRun,
    Traces,
    compare,
    compute_traces,
    lambda_text,
    load_run,
)
from slopetui.sweeps.rest_roots import RestRoots
from slopetui.tui.screens.base import SlopeScreen
from slopetui.tui.widgets.plot_view import PlotView, Renderer
from slopetui.tui.widgets.roots_view import RootsView
from slopetui.tui.widgets.steady_footer import SteadyFooter

__all__ = ["MATCH_TEXT", "RECOMPUTED_NOTE", "RunDetailScreen", "StoredRun", "compare",
           "compute_traces", "recompute_text", "summary_text"]

#: Where the plots come from: the header's subtitle, after the run's id.
RECOMPUTED_NOTE = "traces recomputed on demand, not stored"
#: Peak values shown in the summary; the rest are counted.
PEAKS_SHOWN = 2
#: Columns of a line of the header on an 80-column terminal (its padding: one each side):
#: the width its result items are packed to when none is given.
SUMMARY_WIDTH = 78
#: The columns of the screen's vertical scrollbar (Textual's default), kept free.
SCROLLBAR_COLUMNS = 2
#: Between two result items on a line of the header.
ITEM_SEPARATOR = " · "

#: The spans of the time series that z steps through: periods of the dominant frequency
#: before the window's end, None for the whole window.
ZOOMS: tuple[int | None, ...] = (TIME_PERIODS, 50, None)

#: Tab pane ids, in tab order.
TAB_TIME, TAB_PHASE, TAB_SPECTRUM, TAB_LYAP = "tab-time", "tab-phase", "tab-spectrum", "tab-lyap"
TAB_CERT = "tab-certificate"
TAB_ROOTS = "tab-roots"
#: The header shows a certificate up to its first clause (the rest, often 200 characters,
#: would push the plots off an 80 x 24 screen); the Certificate tab shows it whole.
CERTIFICATE_HEAD = 40


# -- messages from the workers ------------------------------------------------------------

@dataclass
class RunLoaded(Message):
    run: StoredRun


@dataclass
class RunLoadFailed(Message):
    cause: str


@dataclass
class TracesReady(Message):
    generation: int
    traces: Traces


@dataclass
class TracesFailed(Message):
    generation: int
    cause: str


@dataclass
class RootsReady(Message):
    roots: RestRoots


@dataclass
class RootsFailed(Message):
    cause: str


# -- pure helpers ---------------------------------------------------------------------------

def cause_of(exc: BaseException) -> str:
    """An exception as one line for the UI: its type and the first line of its message."""
    lines = str(exc).strip().splitlines()
    return f"{type(exc).__name__}: {lines[0]}" if lines else type(exc).__name__


def last_line(text: str) -> str:
    """The last non-empty line of a stored error (a worker stores the whole traceback;
    its last line names the exception and its cause)."""
    lines = [line for line in text.strip().splitlines() if line.strip()]
    return lines[-1].strip() if lines else ""


def _num(x: float | None, fmt: str = ".4g") -> str:
    return "–" if x is None or not math.isfinite(x) else format(x, fmt)


def _peaks_text(peaks: list[float] | None) -> str:
    values = peaks or []
    shown = ", ".join(f"{p:.3g}" for p in values[:PEAKS_SHOWN])
    more = f", … {len(values) - PEAKS_SHOWN} more" if len(values) > PEAKS_SHOWN else ""
    return f"{len(values)}" + (f" ({shown}{more})" if values else "")


def _largest_modulus(pairs: list[list[float]] | None) -> str:
    values = pairs or []
    if not values:
        return "0"
    return f"{len(values)} (|μ| ≤ {max(abs(complex(re, im)) for re, im in values):.3g})"


def certificate_text(run: StoredRun, width: int) -> str:
    """The Certificate tab: whether and how the attractor was certified, in full, and a
    certified orbit's Floquet multipliers, each against the unit circle. Escaped: the
    certificate is stored text."""
    if not run.done:
        return "no stored result"
    if run.certified is None:
        return "computed before certification: never tried (press r to recompute)"
    said = "certified" if run.certified else "not certified"
    lines = textwrap.wrap(f"{said}: {run.certificate or '–'}", width)
    pairs = run.multipliers or []
    if pairs:
        lines += ["", f"Floquet multipliers (the flow's and the translation's, both 1, "
                      f"apart), {run.slips} slip{'s' if run.slips != 1 else ''} a period:"]
        for i, (re, im) in enumerate(pairs, 1):
            mod = abs(complex(re, im))
            lines.append(f"  μ{i} = {re:+.6f} {im:+.6f}i   |μ| = {mod:.6f}   "
                         f"{'inside' if mod < 1 else 'ON or OUTSIDE'} the unit circle "
                         f"(by {abs(1 - mod):.2g})")
    return terminal_safe_lines("\n".join(lines))


def packed(items: Sequence[str], width: int) -> list[str]:
    """The items joined by ITEM_SEPARATOR into as few lines of at most ``width`` columns
    as fill them in order; an item longer than a line (a long certificate) goes on after
    the one before it, and the screen wraps it."""
    lines: list[str] = []
    for item in items:
        if lines and (len(lines[-1]) + len(ITEM_SEPARATOR) + len(item) <= width
                      or len(item) > width):
            lines[-1] += ITEM_SEPARATOR + item
        else:
            lines.append(item)
    return lines


def summary_text(run: StoredRun, width: int = SUMMARY_WIDTH) -> str:
    """The header of the screen: who the run is, its parameters, its solver settings,
    and its stored result (every field of core.result_fields marked ``detail``, packed
    into lines of ``width`` columns) or, for a run not done, its status and the cause of
    its last error. Escaped (terminal_safe_lines): the status, worker id, regime and error
    are stored text."""
    cached = f" · copied from run {run.cached_from}" if run.cached_from is not None else ""
    who = (f"run {run.id} · sweep {run.sweep_id} · {run.status} · attempts {run.attempts} · "
           f"worker {run.worker_id or '–'} · runtime {_num(run.runtime_s, '.2g')} s{cached}")
    params = (f"a {run.a:g}  b {run.b:g}  c {run.c:g}  d {run.d:g}  k {run.k:g}  "
              f"v {run.v:g}  τ {run.tau:g}  δ {run.delta:g}")
    # the stop rule with the end time it bounds ("stop at t_end 1e+05", "stop certified or
    # t_end 1e+05"): the line stays short enough for 80 columns under the paper's protocol
    # and, for a done certified run, where it stopped (in the same item, not a result
    # line: the 80 x 24 screen keeps lambda_max's note)
    until = "at" if run.stop == "t_end" else f"{run.stop} or"
    stop = f"stop {until} t_end {run.t_end:g}"
    if run.stop != "t_end" and run.done and run.t_stop is not None:
        stop = f"stop {run.stop}: t_stop {run.t_stop:g} of t_end {run.t_end:g}"
    solver = "\n".join(packed([run.method, f"dt {run.dt:g}", stop, f"window {run.window:g}",
                               f"engine {run.engine}"], width))
    if run.inferred:
        what = (f"inferred {run.regime}" if run.done else "inferred failed")
        return terminal_safe_lines("\n".join([
            who, params, solver,
            f"{what}, not computed: its cell's 4 corners agree (level {run.level})",
            "no measurements; r computes this point"]))
    if not run.done:
        error = f"last error: {last_line(run.error)}" if run.error else "no error recorded"
        return terminal_safe_lines("\n".join([who, params, solver,
                                               f"no stored result ({run.status})", error]))
    # escaped item by item: the packing counts the columns the escaped text takes
    items = [terminal_safe_lines(result_item(run, f)) for f in DETAIL_FIELDS]
    return terminal_safe_lines("\n".join([who, params, solver, *packed(items, width)]))


def result_item(run: StoredRun, field: ResultField) -> str:
    """One stored result field as the header shows it, by its kind (core.result_fields):
    the regime with the classifier's detail, lambda_max with its error."""
    value = getattr(run, field.name)
    if field.name == "regime":
        return f"{value}" + (f" ({run.detail})" if run.detail else "")
    if field.name == "lambda_max":
        shown = lambda_text(value, run.lambda_err)
    elif field.kind == "list":
        shown = _peaks_text(value)
    elif field.kind == "pairs":
        shown = _largest_modulus(value)
    elif field.name == "certificate" and value:
        head = str(value).split(":")[0]
        shown = (head if len(head) <= CERTIFICATE_HEAD else head[:CERTIFICATE_HEAD - 1] + "…")
        shown += " (tab c)"
    elif field.kind == "measure":
        shown = _num(value, ".3g")
    elif field.kind == "optional":
        shown = _num(value, "g")
    else:  # text: none stored, or none at all (no flags)
        shown = "–" if value is None or value == "" else str(value)
    return f"{field.shown_as} {shown}"


def recompute_text(run: StoredRun) -> str:
    """What the screen says while it recomputes: the horizon and the expected time."""
    took = run.runtime_s
    if took is not None and math.isfinite(took):
        about = "under 1 s" if took < 1.0 else f"about {took:.0f} s"
        return f"recomputing (t_end = {run.t_end:g}, {about})…"
    return f"recomputing (t_end = {run.t_end:g})…"


def time_series_renderer(traces: Traces, periods: int | None = TIME_PERIODS) -> Renderer:
    """The time series of the recomputed traces: the last ``periods`` periods of their
    dominant frequency, or the whole window (None)."""
    def time_series(w: int, h: int, c: bool) -> str:
        return render_time_series(traces.t, traces.m_x, traces.m_y,
                                  frequency=traces.summary.frequency, periods=periods,
                                  width=w, height=h, color=c)
    return time_series


def renderers(traces: Traces, periods: int | None = TIME_PERIODS) -> dict[str, Renderer]:
    """One PlotView renderer per tab, drawing the recomputed traces; the time series over
    the last ``periods`` periods (None: the whole window)."""
    t, m_x, m_y = traces.t, traces.m_x, traces.m_y
    estimate = traces.lyap.format() if traces.lyap else ""
    time_series = time_series_renderer(traces, periods)

    def phase(w: int, h: int, c: bool) -> str:
        return render_phase_portrait(t, m_x, m_y, width=w, height=h, color=c)

    def spectrum(w: int, h: int, c: bool) -> str:
        return render_spectrum(traces.freq, traces.power, width=w, height=h, color=c)

    def lyapunov(w: int, h: int, c: bool) -> str:
        # the note (which map, its bias) wrapped under the legend: the plot's legend
        # would cut a line longer than the plot ("…"), and it is 90-110 columns
        note = textwrap.wrap(traces.lambda_note, w, initial_indent="- ",
                             subsequent_indent="  ")
        plot = render_lyapunov(traces.lam_t, traces.lam, estimate=estimate, width=w,
                               height=h - len(note), color=c)
        return "\n".join([plot, *note])

    return {TAB_TIME: time_series, TAB_PHASE: phase, TAB_SPECTRUM: spectrum,
            TAB_LYAP: lyapunov}


# -- the screen -----------------------------------------------------------------------------

class RunDetailScreen(SlopeScreen[None]):
    """One run: its parameters, stored summary, and recomputed trace plots."""

    BINDINGS = [
        Binding("escape", "back", "Back", id="run_detail.back"),
        Binding("r", "recompute", "Recompute", id="run_detail.recompute"),
        Binding("z", "zoom", "Zoom", id="run_detail.zoom"),
        Binding("f", "figure", "Figure", id="run_detail.figure"),
        Binding("m", "mark", "Mark", id="run_detail.mark"),
        Binding("u", "rerun", "Certified re-run", id="run_detail.rerun", show=False,
                tooltip="Queue this run again with stop = certified (a one-run sweep)"),
        Binding("o", "orbit", "Orbit", id="run_detail.orbit", show=False,
                tooltip="The periodic orbit at this run's point, with its multipliers"),
        # the tabs are on screen and clickable: their keys stay out of the footer (80 columns)
        Binding("t", f"show_tab('{TAB_TIME}')", "Time", id="run_detail.tab_time", show=False),
        Binding("p", f"show_tab('{TAB_PHASE}')", "Phase", id="run_detail.tab_phase",
                show=False),
        Binding("s", f"show_tab('{TAB_SPECTRUM}')", "Spectrum", id="run_detail.tab_spectrum",
                show=False),
        Binding("l", f"show_tab('{TAB_LYAP}')", "λmax", id="run_detail.tab_lyap", show=False),
        Binding("c", f"show_tab('{TAB_CERT}')", "Certificate", id="run_detail.tab_certificate",
                show=False),
        Binding("e", f"show_tab('{TAB_ROOTS}')", "Roots", id="run_detail.tab_roots",
                show=False, tooltip="The rest state's characteristic roots at this point"),
    ]

    def __init__(self, run_id: int) -> None:
        super().__init__()
        self.run_id = run_id
        self.run: StoredRun | None = None
        #: The traces on show (the figure key draws them; None until recomputed).
        self.traces: Traces | None = None
        #: Bumped by each recomputation: results of an older one are dropped (a thread
        #: worker cannot be stopped mid-integration, only ignored).
        self._generation = 0
        #: Which of ZOOMS the time series shows (kept across recomputations).
        self.zoom = 0
        #: The rest state's roots at the run's point (None until the Roots tab asked for
        #: them and they came); whether they were asked for.
        self.roots: RestRoots | None = None
        self._roots_asked = False

    def compose(self) -> ComposeResult:
        yield Header()
        yield Static(f"run {self.run_id}: loading…", id="run-summary", markup=False)
        yield Static("", id="run-status", markup=False)
        with TabbedContent(id="run-tabs"):
            with TabPane("Time series", id=TAB_TIME):
                yield PlotView(id="plot-time")
            with TabPane("Phase portrait", id=TAB_PHASE):
                yield PlotView(id="plot-phase")
            with TabPane("Spectrum", id=TAB_SPECTRUM):
                yield PlotView(id="plot-spectrum")
            with TabPane("λmax", id=TAB_LYAP):
                yield PlotView(id="plot-lyap")
            with TabPane("Certificate", id=TAB_CERT), VerticalScroll(id="certificate-pane"):
                yield Static("", id="certificate-text", markup=False)
                # a certified orbit's multipliers drawn against the unit circle, under
                # their list; hidden for a run without them (a fixed point, no certificate)
                yield PlotView(id="plot-multipliers")
            with TabPane("Roots", id=TAB_ROOTS):
                yield RootsView(id="roots-view")
        yield SteadyFooter()

    def on_mount(self) -> None:
        self.sub_title = f"run {self.run_id} · {RECOMPUTED_NOTE}"
        self.refresh_data()

    def refresh_data(self) -> None:
        """Load the run once the store is open (the app calls this when it opens)."""
        if self.run is not None:
            return
        if self.db is None:
            self._status("waiting for the database to open…")
            return
        self._status(f"loading run {self.run_id}…")
        self.load_run()

    # -- workers -------------------------------------------------------------------------

    @work(thread=True, exclusive=True, group="run-detail-load")
    def load_run(self) -> None:
        db = self.db
        if db is None:  # refresh_data waits for it; the app never closes it again
            return
        try:
            run = load_run(db, self.run_id)
        except Exception as exc:  # any database failure is shown with its cause
            self.post_message(RunLoadFailed(f"the database could not be read: {cause_of(exc)}"))
            return
        if run is None:
            self.post_message(RunLoadFailed(f"there is no run {self.run_id} in this store"))
        else:
            self.post_message(RunLoaded(run))

    @work(thread=True, exclusive=True, group="run-detail-recompute")
    def recompute(self, params: Params, settings: SolverSettings, generation: int) -> None:
        worker = get_current_worker()
        try:
            traces = compute_traces(params, settings,
                                    None if self.run is None else self.run.carried_state())
        except Exception as exc:  # a failed integration is reported, never a traceback
            if not worker.is_cancelled:
                self.post_message(TracesFailed(generation, cause_of(exc)))
            return
        if not worker.is_cancelled:
            self.post_message(TracesReady(generation, traces))

    @work(thread=True, exclusive=True, group="run-detail-roots")
    def compute_roots(self, params: Params) -> None:
        """The rest state's roots at the run's point (a fraction of a second; computed
        only when the Roots tab is first shown)."""
        try:
            found = rest_roots.compute(params)
        except Exception as exc:  # a root that cannot be carried, say: shown, never raised
            self.post_message(RootsFailed(cause_of(exc)))
            return
        self.post_message(RootsReady(found))

    # -- messages from the workers ---------------------------------------------------------

    def on_run_loaded(self, message: RunLoaded) -> None:
        run = self.run = message.run
        self._show_summary()
        self._ask_roots()
        if run.inferred:
            self._status("inferred, not computed: nothing to plot; press r to compute it")
        elif run.done:
            self.start_recompute()
        else:
            self._status(f"status {run.status}: no stored result to plot; press r to "
                         f"compute the traces anyway")

    def on_run_load_failed(self, message: RunLoadFailed) -> None:
        self.query_one("#run-summary", Static).update(f"run {self.run_id}: cannot be shown")
        self._status(message.cause, "error")

    def on_traces_ready(self, message: TracesReady) -> None:
        if message.generation != self._generation or self.run is None:
            return
        self._loading(False)
        self.traces = message.traces
        for tab, renderer in renderers(message.traces, ZOOMS[self.zoom]).items():
            self._plot(tab).show(renderer)
        verdict = compare(self.run, message.traces, source_digest())
        self._status(verdict.text, "ok" if verdict.ok else "warning")

    def on_roots_ready(self, message: RootsReady) -> None:
        self.roots = message.roots
        self.query_one(RootsView).show(message.roots)

    def on_roots_failed(self, message: RootsFailed) -> None:
        self.query_one(RootsView).say(f"the roots at this point cannot be computed: "
                                      f"{message.cause}")

    def on_tabbed_content_tab_activated(self, event: TabbedContent.TabActivated) -> None:
        self._ask_roots()

    def _ask_roots(self) -> None:
        """Compute the roots once, when the Roots tab is on show and the run is read."""
        tabs = self.query_one("#run-tabs", TabbedContent)
        if self._roots_asked or self.run is None or tabs.active != TAB_ROOTS:
            return
        self._roots_asked = True
        view = self.query_one(RootsView)
        try:
            params = Params(**{n: getattr(self.run, n) for n in PARAM_NAMES})
        except ParameterError as exc:
            view.say(f"no roots: {exc}")
            return
        view.say("computing the rest state's roots…")
        self.compute_roots(params)

    def on_traces_failed(self, message: TracesFailed) -> None:
        if message.generation != self._generation:
            return
        self._loading(False)
        self._status(f"recomputation failed: {message.cause}", "error")

    # -- actions ---------------------------------------------------------------------------

    def analysis_point(self) -> tuple[Params, str] | None:
        """Where an analysis opened from here starts (SlopeApp.analysis_point): this run's
        point; None until it is read."""
        run = self.run
        if run is None:
            return None
        return Params(**{n: getattr(run, n) for n in PARAM_NAMES}), f"run {run.id}'s point"

    def action_rerun(self) -> None:
        """The form that queues this run again with the certified stop."""
        self.app.certified_rerun(self.run_id)

    def action_orbit(self) -> None:
        """The orbit form at this run's point."""
        self.app.open_analysis("orbit")

    def action_back(self) -> None:
        self.dismiss(None)

    def action_recompute(self) -> None:
        if self.run is None:
            self.notify("the run is not loaded yet", severity="warning")
            return
        self.start_recompute()

    def action_show_tab(self, tab: str) -> None:
        self.query_one("#run-tabs", TabbedContent).active = tab

    def action_mark(self) -> None:
        self.app.toggle_mark(self.run_id)

    def action_zoom(self) -> None:
        """The time series' next span of ZOOMS, brought into view (z acts on it alone)."""
        self.zoom = (self.zoom + 1) % len(ZOOMS)
        self.action_show_tab(TAB_TIME)
        if self.traces is not None:
            self._plot(TAB_TIME).show(time_series_renderer(self.traces, ZOOMS[self.zoom]))

    def action_figure(self) -> None:
        """Write the four panels on show as a figure (slopetui figure --run ID)."""
        if self.run is None or self.traces is None:
            self.notify("nothing to draw yet: the traces are not recomputed (r)", severity="warning")
            return
        self.notify(f"drawing the figure of run {self.run_id}…")
        self.app.write_runs_figure([(self.run, self.traces)])

    def start_recompute(self) -> None:
        """Recompute the loaded run in a worker, if its inputs are valid."""
        assert self.run is not None
        try:
            params, settings = self.run.inputs()
        except ParameterError as exc:
            self._status(f"cannot recompute: {exc}", "error")
            return
        self._generation += 1
        self.traces = None
        self._loading(True)
        self._status(recompute_text(self.run))
        self.recompute(params, settings, self._generation)

    # -- widgets ---------------------------------------------------------------------------

    def on_resize(self, event: events.Resize) -> None:
        self._show_summary()  # packed to the new width

    def _show_summary(self) -> None:
        if self.run is not None:
            summary = self.query_one("#run-summary", Static)
            width = self.size.width - summary.styles.gutter.width
            summary.update(summary_text(self.run, max(width, 20)))
            self.call_after_refresh(self._repack_if_scrolled, width)
            self.query_one("#certificate-text", Static).update(
                certificate_text(self.run, max(width - 2, 20)))
            self._show_multipliers(self.run)

    def _repack_if_scrolled(self, width: int) -> None:
        """A summary taller than the room the plot leaves scrolls the screen, whose
        scrollbar then takes two columns: packed to the full width, its lines were
        wrapped again two columns short (an item cut across two lines). Packed again to
        the narrower width once the screen scrolls."""
        if self.run is not None and self.max_scroll_y > 0:
            narrower = max(width - SCROLLBAR_COLUMNS, 20)
            self.query_one("#run-summary", Static).update(summary_text(self.run, narrower))

    def _show_multipliers(self, run: StoredRun) -> None:
        plot = self.query_one("#plot-multipliers", PlotView)
        pairs = list(run.multipliers or [])
        plot.display = bool(pairs) and run.done
        if plot.display:
            title = f"run {run.id}: Floquet multipliers and |μ| = 1"
            plot.show(lambda width, height, color: render_multipliers(
                pairs, title=title, width=width, height=height, color=color))

    def _status(self, text: str, kind: str = "") -> None:
        status = self.query_one("#run-status", Static)
        status.set_classes(kind)
        status.update(text)

    def _loading(self, on: bool) -> None:
        self.query_one("#run-tabs", TabbedContent).loading = on

    def _plot(self, tab: str) -> PlotView:
        return self.query_one(f"#{tab} PlotView", PlotView)
