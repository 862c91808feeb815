"""The run detail screen: one run's parameters and stored summary, and four plots of its
traces (m_x and m_y against time over the analysis window, the phase portrait, the power
spectrum of m_y, the running lambda_max estimate converging).

**The traces are recomputed on demand, not stored.** The model is deterministic: the
run's parameters and solver settings integrated again give the trajectory the worker
saw (bit for bit with the same engine on the same machine). Storing it would cost
~4 MB per run (a 1000-unit window is 1e5 samples of 5 variables) for a plot that is
looked at for a few runs of a sweep; the store keeps the summaries only. Opening a
finished run recomputes it in a thread worker (as long as the worker took, usually
well under a second at RK4), then compares the recomputed regime and lambda_max with
the stored ones, and says when they differ and whether the engine changed since.

Runs that are not done (queued, running, failed, cancelled) show their status and
stored error; their traces are computed only on request (r), and only when their
inputs are valid. So are the *inferred* runs of an adaptive sweep: the screen says that
their regime was inferred from their cell's corners, not computed, and r computes them
(and compares the computed regime with the inferred one). Every database call and computation runs in a thread worker and
reports back with a message; widgets are touched on the UI thread only.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np
from textual import work
from textual.app import ComposeResult
from textual.binding import Binding
from textual.message import Message
from textual.screen import Screen
from textual.widgets import Footer, Header, Static, TabbedContent, TabPane
from textual.worker import get_current_worker

from core import ParameterError, Params, SolverSettings, run_point
from core.classify import Summary, power_spectrum
from core.jit_cache import source_digest
from core.lyapunov import LyapunovEstimate, running
from core.params import PARAM_NAMES
from slopetui.plots.run_plots import (
    render_lyapunov,
    render_phase_portrait,
    render_spectrum,
    render_time_series,
)
from slopetui.store.models import Run
from slopetui.tui.widgets.plot_view import PlotView, Renderer

#: The one line that says where the plots come from.
RECOMPUTED_NOTE = "Traces are recomputed on demand (the store keeps summaries only)."
MATCH_TEXT = "recomputed: matches the stored result"
#: Two lambda_max values are "the same" within this relative difference (last digits of
#: a sum over ~1e4 renormalisations, which FMA contraction may reorder across machines).
LAMBDA_REL_TOL = 1e-6
#: ... or, failing that, "agree within error" within this many combined standard errors.
LAMBDA_SIGMAS = 3.0
#: Peak values shown in the summary; the rest are counted.
PEAKS_SHOWN = 2

#: Tab pane ids, in tab order.
TAB_TIME, TAB_PHASE, TAB_SPECTRUM, TAB_LYAP = "tab-time", "tab-phase", "tab-spectrum", "tab-lyap"


@dataclass(frozen=True, slots=True)
class StoredRun:
    """The columns of a Run row this screen shows, copied out of the session.

    Field names are the Run attributes. Measurements are NaN where undefined or not
    computed yet (``Measure``); t_blowup is None when the run did not blow up.
    """

    id: int
    sweep_id: int
    status: str
    a: float
    b: float
    c: float
    d: float
    k: float
    v: float
    tau: float
    delta: float
    method: str
    dt: float
    t_end: float
    window: float
    lyap: bool
    engine: str
    worker_id: str | None
    attempts: int
    error: str | None
    cached_from: int | None
    regime: str | None
    detail: str | None
    lambda_max: float
    lambda_err: float
    amplitude: float
    period: float
    period_count: int | None
    peaks: list[float] | None
    frequency: float
    drift: float
    t_blowup: float | None
    runtime_s: float | None
    inferred: bool = False
    level: int | None = None

    @classmethod
    def of(cls, run: Run) -> StoredRun:
        return cls(**{f.name: getattr(run, f.name) for f in fields(cls)})

    @property
    def done(self) -> bool:
        return self.status == "done"

    def inputs(self) -> tuple[Params, SolverSettings]:
        """The run's parameters and solver settings, lambda_max always on (its running
        estimate is one of the plots). Raises ParameterError for invalid inputs."""
        params = Params(**{n: getattr(self, n) for n in PARAM_NAMES})
        settings = SolverSettings(method=self.method, dt=self.dt, t_end=self.t_end,
                                  window=self.window, lyap=True)
        return params, settings


@dataclass(frozen=True, slots=True)
class Traces:
    """What a recomputation gives the plots, in model units: the analysis window
    (t, m_x, m_y), the spectrum of m_y (frequency in 1/time), the running lambda_max
    (lam_t, lam in 1/time), and the recomputed summary."""

    t: np.ndarray
    m_x: np.ndarray
    m_y: np.ndarray
    freq: np.ndarray
    power: np.ndarray
    lam_t: np.ndarray
    lam: np.ndarray
    summary: Summary
    lyap: LyapunovEstimate | None


@dataclass(frozen=True, slots=True)
class Verdict:
    """The recomputed result against the stored one: ``ok`` False is a warning."""

    ok: bool
    text: str


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


def compute_traces(params: Params, settings: SolverSettings) -> Traces:
    """Integrate the run again (seconds: as long as the run took) and derive the plots' data."""
    result = run_point(params, settings)
    tr = result.trajectory
    t, m_x, m_y = tr.window_t, tr.window[0], tr.window[1]
    freq, power = power_spectrum(t, m_y)
    lam_t, lam = running(tr.lyap_logs, tr.grid.renorm_interval)
    return Traces(t, m_x, m_y, freq, power, lam_t, lam, result.summary, result.lyap)


def _num(x: float | None, fmt: str = ".4g") -> str:
    return "–" if x is None or not math.isfinite(x) else format(x, fmt)


def _lambda_text(value: float, error: float) -> str:
    if not math.isfinite(value):
        return "–"
    return f"{value:.3g} ± {error:.2g}" if math.isfinite(error) else f"{value:.3g}"


def _peaks_text(peaks: list[float] | None) -> str:
    values = peaks or []
    shown = ", ".join(f"{p:.3g}" for p in values[:PEAKS_SHOWN])
    more = f", … {len(values) - PEAKS_SHOWN} more" if len(values) > PEAKS_SHOWN else ""
    return f"{len(values)}" + (f" ({shown}{more})" if values else "")


def summary_text(run: StoredRun) -> str:
    """The header of the screen, five lines: who the run is, its parameters, its solver
    settings, and its stored result or, for a run not done, its status and the cause of
    its last error."""
    cached = f" · copied from run {run.cached_from}" if run.cached_from is not None else ""
    who = (f"run {run.id} · sweep {run.sweep_id} · {run.status} · attempts {run.attempts} · "
           f"worker {run.worker_id or '–'} · runtime {_num(run.runtime_s, '.2g')} s{cached}")
    params = (f"a {run.a:g}  b {run.b:g}  c {run.c:g}  d {run.d:g}  k {run.k:g}  "
              f"v {run.v:g}  τ {run.tau:g}  δ {run.delta:g}")
    solver = (f"{run.method} · dt {run.dt:g} · t_end {run.t_end:g} · window {run.window:g} · "
              f"engine {run.engine}")
    if run.inferred:
        what = (f"inferred {run.regime}" if run.done else "inferred failed")
        return "\n".join([who, params, solver,
                          f"{what}, not computed: its cell's 4 corners agree (level {run.level})",
                          "no measurements; r computes this point"])
    if not run.done:
        error = f"last error: {last_line(run.error)}" if run.error else "no error recorded"
        return "\n".join([who, params, solver, f"no stored result ({run.status})", error])
    detail = f" ({run.detail})" if run.detail else ""
    result = (f"{run.regime}{detail} · λmax {_lambda_text(run.lambda_max, run.lambda_err)} · "
              f"amplitude {_num(run.amplitude, '.3g')} · period {_num(run.period, '.3g')}")
    more = (f"peaks {_peaks_text(run.peaks)} · drift {_num(run.drift, '.3g')} · "
            f"t_blowup {_num(run.t_blowup, 'g')}")
    return "\n".join([who, params, solver, result, more])


def recompute_text(run: StoredRun) -> str:
    """What the screen says while it recomputes: the horizon and the expected time."""
    took = run.runtime_s
    if took is not None and math.isfinite(took):
        about = "under 1 s" if took < 1.0 else f"about {took:.0f} s"
        return f"recomputing (t_end = {run.t_end:g}, {about})…"
    return f"recomputing (t_end = {run.t_end:g})…"


def _same_lambda(a: float, b: float) -> bool:
    if not (math.isfinite(a) and math.isfinite(b)):
        return not math.isfinite(a) and not math.isfinite(b)
    return abs(a - b) <= LAMBDA_REL_TOL * max(abs(a), abs(b), 1e-12)


def _within_error(a: float, err_a: float, b: float, err_b: float) -> bool:
    sigma = math.hypot(err_a, err_b)
    return math.isfinite(sigma) and abs(a - b) <= LAMBDA_SIGMAS * sigma


def compare(run: StoredRun, traces: Traces, engine_now: str) -> Verdict:
    """The recomputed regime and lambda_max against the stored ones.

    Equal regimes and lambda_max equal to LAMBDA_REL_TOL match; lambda_max within
    LAMBDA_SIGMAS combined errors "agrees within error"; anything else is a warning that
    names the likely cause: an engine changed since the run (``run.engine`` against
    ``engine_now``), or else the machine or library versions.
    """
    s, lyap = traces.summary, traces.lyap
    lam, err = (lyap.value, lyap.error) if lyap else (math.nan, math.nan)
    engine_changed = run.engine != engine_now
    engine_note = (f"the engine changed since the run (stored {run.engine}, now {engine_now})"
                   if engine_changed else "")
    if run.inferred:
        computed = f"computed: {s.regime} ({s.detail}), λmax {_lambda_text(lam, err)}"
        if not run.done:
            return Verdict(True, f"{computed} · inferred failed, nothing to compare")
        if s.regime == run.regime:
            return Verdict(True, f"{computed} · the inferred regime was right")
        return Verdict(False, f"warning: {computed}; the inferred regime was {run.regime}")
    if not run.done:
        return Verdict(True, f"computed: {s.regime} ({s.detail}), λmax {_lambda_text(lam, err)}"
                             f" · nothing stored to compare ({run.status})")
    # a run stored without lambda_max (lyap off) has nothing to compare it with
    lambda_stored = run.lyap or math.isfinite(run.lambda_max)
    same_regime = s.regime == run.regime
    same_lambda = not lambda_stored or _same_lambda(lam, run.lambda_max)
    if same_regime and same_lambda:
        return Verdict(True, MATCH_TEXT + (f" ({engine_note})" if engine_changed else ""))
    if same_regime and _within_error(lam, err, run.lambda_max, run.lambda_err):
        return Verdict(True, f"{MATCH_TEXT} in regime; λmax {_lambda_text(lam, err)} agrees "
                             f"with the stored one within error"
                             + (f" ({engine_note})" if engine_changed else ""))
    why = engine_note or "same engine: another machine or library version?"
    return Verdict(False, f"warning: recomputed {s.regime}, λmax {_lambda_text(lam, err)}; "
                          f"stored {run.regime}, λmax "
                          f"{_lambda_text(run.lambda_max, run.lambda_err)}; {why}")


def renderers(traces: Traces) -> dict[str, Renderer]:
    """One PlotView renderer per tab, drawing the recomputed traces."""
    t, m_x, m_y = traces.t, traces.m_x, traces.m_y
    estimate = traces.lyap.format() if traces.lyap else ""

    def time_series(w: int, h: int, c: bool) -> str:
        return render_time_series(t, m_x, m_y, width=w, height=h, color=c)

    def phase(w: int, h: int, c: bool) -> str:
        return render_phase_portrait(t, m_x, m_y, width=w, height=h, color=c)

    def spectrum(w: int, h: int, c: bool) -> str:
        return render_spectrum(traces.freq, traces.power, width=w, height=h, color=c)

    def lyapunov(w: int, h: int, c: bool) -> str:
        return render_lyapunov(traces.lam_t, traces.lam, estimate=estimate, width=w,
                               height=h, color=c)

    return {TAB_TIME: time_series, TAB_PHASE: phase, TAB_SPECTRUM: spectrum,
            TAB_LYAP: lyapunov}


# -- the screen -----------------------------------------------------------------------------

class RunDetailScreen(Screen[None]):
    """One run: its parameters, stored summary, and recomputed trace plots."""

    BINDINGS = [
        Binding("escape", "back", "Back", id="run_detail.back"),
        Binding("r", "recompute", "Recompute", id="run_detail.recompute"),
        Binding("t", f"show_tab('{TAB_TIME}')", "Time", id="run_detail.tab_time"),
        Binding("p", f"show_tab('{TAB_PHASE}')", "Phase", id="run_detail.tab_phase"),
        Binding("s", f"show_tab('{TAB_SPECTRUM}')", "Spectrum", id="run_detail.tab_spectrum"),
        Binding("l", f"show_tab('{TAB_LYAP}')", "λmax", id="run_detail.tab_lyap"),
    ]

    def __init__(self, run_id: int) -> None:
        super().__init__()
        self.run_id = run_id
        self.run: StoredRun | None = None
        #: Bumped by each recomputation: results of an older one are dropped (a thread
        #: worker cannot be stopped mid-integration, only ignored).
        self._generation = 0

    def compose(self) -> ComposeResult:
        yield Header()
        yield Static(f"run {self.run_id}: loading…", id="run-summary", markup=False)
        yield Static(RECOMPUTED_NOTE, id="run-note", markup=False)
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
        yield Footer()

    def on_mount(self) -> None:
        self.sub_title = f"run {self.run_id}"
        self.refresh_data()

    def refresh_data(self) -> None:
        """Load the run once the store is open (the app calls this when it opens)."""
        if self.run is not None:
            return
        if getattr(self.app, "db", None) is None:
            self._status("waiting for the database to open…")
            return
        self._status(f"loading run {self.run_id}…")
        self.load_run()

    # -- workers -------------------------------------------------------------------------

    @work(thread=True, exclusive=True, group="run-detail-load")
    def load_run(self) -> None:
        db = getattr(self.app, "db", None)
        try:
            with db.sessions() as session:
                row = session.get(Run, self.run_id)
                run = StoredRun.of(row) if row is not None else None
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
            traces = compute_traces(params, settings)
        except Exception as exc:  # a failed integration is reported, never a traceback
            if not worker.is_cancelled:
                self.post_message(TracesFailed(generation, cause_of(exc)))
            return
        if not worker.is_cancelled:
            self.post_message(TracesReady(generation, traces))

    # -- messages from the workers ---------------------------------------------------------

    def on_run_loaded(self, message: RunLoaded) -> None:
        run = self.run = message.run
        self.query_one("#run-summary", Static).update(summary_text(run))
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
        for tab, renderer in renderers(message.traces).items():
            self._plot(tab).show(renderer)
        verdict = compare(self.run, message.traces, source_digest())
        self._status(verdict.text, "ok" if verdict.ok else "warning")

    def on_traces_failed(self, message: TracesFailed) -> None:
        if message.generation != self._generation:
            return
        self._loading(False)
        self._status(f"recomputation failed: {message.cause}", "error")

    # -- actions ---------------------------------------------------------------------------

    def action_back(self) -> None:
        self.dismiss(None)

    def action_recompute(self) -> None:
        if self.run is None:
            self.notify("the run is not loaded yet", severity="warning")
            return
        self.start_recompute()

    def action_show_tab(self, tab: str) -> None:
        self.query_one("#run-tabs", TabbedContent).active = tab

    def start_recompute(self) -> None:
        """Recompute the loaded run in a worker, if its inputs are valid."""
        assert self.run is not None
        try:
            params, settings = self.run.inputs()
        except ParameterError as exc:
            self._status(f"cannot recompute: {exc}", "error")
            return
        self._generation += 1
        self._loading(True)
        self._status(recompute_text(self.run))
        self.recompute(params, settings, self._generation)

    # -- widgets ---------------------------------------------------------------------------

    def _status(self, text: str, kind: str = "") -> None:
        status = self.query_one("#run-status", Static)
        status.set_classes(kind)
        status.update(text)

    def _loading(self, on: bool) -> None:
        self.query_one("#run-tabs", TabbedContent).loading = on

    def _plot(self, tab: str) -> PlotView:
        return self.query_one(f"#{tab} PlotView", PlotView)
