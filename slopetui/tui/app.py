"""The slopetui application: sweeps, new sweep, run detail, queue, SQL console and
continuations (branches).

``slopetui`` with no arguments opens it on the default database and starts a detached
local worker pool, or attaches to the one already running on this host
(``slopetui.tui.worker_pool``).

What takes time (opening the store, the pool, pausing a sweep, writing a figure or an
export) is a background action: a function run in a thread worker, whose outcome comes
back to the UI thread in one way (``slopetui.tui.background``).

Keys: the footer of every screen shows the app's two (? help, ctrl+q quit) besides the
screen's own; the others (1-4, n, v) are in the help (? or F1, generated from the
bindings) and in the command palette (ctrl+p, ``slopetui.tui.commands``), which also
takes what a key cannot (open run 12, new sweep from a preset, export a sweep).

The run detail and compare screens are imported when first opened: they recompute runs
(``slopetui.sweeps.recompute``), which loads numba and scipy, 0.28 s of CPU (241 modules;
``python -X importtime``, measured after the application's own imports) that an
application showing only stored results never needs.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable, Iterable, Sequence
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, Any

from rich.text import Text
from textual import on
from textual.app import App, SystemCommand
from textual.binding import Binding
from textual.screen import Screen
from textual.widget import AwaitMount
from textual.widgets import Select
from textual.worker import Worker

from core.params import Params
from slopetui.display_text import terminal_safe_lines
from slopetui.store.database import Database
from slopetui.store.open import open_store
from slopetui.store.queries import sweep_engines
from slopetui.store.runs.marks import clear_marks, marked_runs, set_mark
from slopetui.sweeps import control, export_files
from slopetui.sweeps.fold_overlay import Curve
from slopetui.tui import figure_writing
from slopetui.tui.background import BackgroundActions
from slopetui.tui.commands import SlopeCommands
from slopetui.tui.screens import analyses
from slopetui.tui.screens.analysis_form import AnalysisFormScreen
from slopetui.tui.screens.base import SlopeScreen
from slopetui.tui.screens.branches import BranchesScreen
from slopetui.tui.screens.confirm import ConfirmScreen
from slopetui.tui.screens.error import StoreChoice, StoreErrorScreen
from slopetui.tui.screens.help import HelpScreen
from slopetui.tui.screens.new_sweep import NewSweepScreen
from slopetui.tui.screens.queue import QueueScreen
from slopetui.tui.screens.sql import SqlScreen
from slopetui.tui.screens.sweeps import SweepsScreen
from slopetui.tui.worker_pool import attach_pool

if TYPE_CHECKING:
    from slopetui.sweeps.diagram import SweepDiagram
    from slopetui.sweeps.recompute import StoredRun, Traces

#: Seconds between refreshes of the live views (progress, diagrams, workers).
REFRESH_S = 2.0


#: What the sweeps screen says while there is no store (SlopeApp.store_status).
OPENING_STORE = "Opening the store…"


# inherit_bindings=False: App's own ctrl+q (hidden, and first in the footer's order) is
# replaced by the one below, shown after "? Help"; ctrl+c's reminder is kept.
class SlopeApp(App[None], inherit_bindings=False):
    """The researcher's cockpit over one store."""

    CSS_PATH = "slopetui.tcss"
    TITLE = "slopetui"
    SUB_TITLE = "mean-field spring-block landslide model"
    MODES = {"sweeps": SweepsScreen, "queue": QueueScreen, "sql": SqlScreen,
             "branches": BranchesScreen}
    DEFAULT_MODE = "sweeps"
    # Textual's system commands (theme, keys, screenshot...) and slopetui's own.
    COMMANDS = App.COMMANDS | {SlopeCommands}
    # In every footer: "? Help" and "^q Quit" only (with Textual's "^p palette"), so that
    # each screen's own keys fit 80 columns. The rest are in the help and the palette.
    BINDINGS = [
        # not priority: a focused text field takes "?" (F1 still opens the help there)
        Binding("question_mark,f1", "help", "Help", id="help",
                tooltip="List every key of this screen, the hidden ones too"),
        # priority: quits from every screen, the SQL editor included, where q is typed
        Binding("ctrl+q", "quit", "Quit", id="quit", priority=True,
                tooltip="Quit slopetui (q too, where no text field has focus); the worker pool "
                        "keeps running, queued work is kept"),
        # not priority: a focused Input or TextArea still gets the letter
        Binding("q", "quit", "Quit", id="quit.q", show=False,
                tooltip="Quit (where no text field has focus; ctrl+q quits everywhere)"),
        Binding("ctrl+c", "help_quit", show=False, system=True),
        Binding("1", "switch_mode('sweeps')", "Sweeps", id="mode.sweeps", show=False,
                tooltip="The sweeps and the selected sweep's diagram"),
        Binding("2", "switch_mode('queue')", "Queue", id="mode.queue", show=False,
                tooltip="The workers and the queue; pause, resume, cancel a sweep"),
        Binding("3", "switch_mode('sql')", "SQL", id="mode.sql", show=False,
                tooltip="Read-only SQL over the store"),
        Binding("4", "switch_mode('branches')", "Branches", id="mode.branches", show=False,
                tooltip="Continuations: branches of periodic orbits and their folds"),
        Binding("n", "new_sweep", "New sweep", id="new_sweep", show=False,
                tooltip="Design a sweep (a preset from the palette fills the form)"),
        # marking a run says "v compares them"
        Binding("v", "compare", "Compare", id="compare", show=False,
                tooltip="Compare the runs marked with m (two or more)"),
        # only while the store could not be opened (check_action): the sweeps screen names it
        Binding("ctrl+o", "store_dialog", "Retry store", id="store", show=False,
                tooltip="Retry opening the store, or open another one"),
    ]

    def __init__(self, db_url: str | None = None, *, start_workers: bool = True,
                 refresh_s: float = REFRESH_S) -> None:
        super().__init__()
        self.db_url = db_url
        self.start_workers = start_workers
        self.refresh_s = refresh_s
        self.db: Database | None = None
        #: Fold-of-cycles curves by sweep id, computed on request (seconds to minutes
        #: each) and kept for the session: a sweep's spec never changes.
        self.fold_curves: dict[int, Curve] = {}
        #: Runs marked with m for the compare screen (v), in the order marked: the store's
        #: (store.runs.marks), read once it is open, so that they survive a restart.
        self.marked: list[int] = []
        #: The marks' writes asked for and not yet done, the first under way
        #: (``_write_marks``): the store gets them in the order pressed.
        self._mark_writes: deque[tuple[Callable[[], object], Callable[[Exception], None]]] = \
            deque()
        #: Where the figure key (f) and the palette's exports write: $SLOPETUI_FIGURES,
        #: else the user data folder's figures/ (figure_writing.default_folder).
        self.figure_folder = figure_writing.default_folder()
        #: Why the store could not be opened (None: it is open, or being opened).
        self.store_error: str | None = None
        #: The modes whose screen is built (the default one from the start), and whether
        #: the switch under way goes to one of them (``switch_mode``).
        self._built_modes = {self.DEFAULT_MODE}
        self._switching_to_built = False
        self.background = BackgroundActions(self)

    # -- switching modes --

    def switch_mode(self, mode: str) -> AwaitMount:
        """Textual's switch, without its hold on updates (``delay_update``) when the
        mode's screen is built already.

        Textual holds every update for 50 ms on a switch, to mask the composing of a new
        screen. A built screen has nothing to mask, and the hold cost twice: the 50 ms
        themselves, and while updates are held Textual runs the callbacks meant for after
        the next refresh at once, so the catch-up of the screen switched to (the garbage
        collection and the reload of its data, ``SlopeScreen._back_in_view``) ran before
        the screen was drawn: 20-90 ms after the key, the drawing at 100-400 ms (a trace
        of 60 switches, 100 x 100 sweep, 2 workers busy). Without the hold the screen is
        drawn first; benchmarks/bench_tui.py, two runs each at load 3-4: every switch's
        median 109-119 ms before, 57-64 ms after, p95 219-229 ms before, 117-140 after."""
        self._switching_to_built = mode in self._built_modes
        try:
            switched = super().switch_mode(mode)
        finally:
            self._switching_to_built = False
        self._built_modes.add(mode)
        return switched

    def delay_update(self, delay: float = 0.05) -> None:
        if not self._switching_to_built:  # switch_mode says why
            super().delay_update(delay)

    def on_mount(self) -> None:
        self.open_store()

    @on(Worker.StateChanged)
    def _worker_state_changed(self, event: Worker.StateChanged) -> None:
        self.background.ended(event)  # a background action's outcome (slopetui.tui.background)

    # -- keys, help and the palette --

    def check_action(self, action: str, parameters: tuple[object, ...]) -> bool | None:
        if action == "store_dialog":  # only while there is a failure to act on
            return self.store_error is not None
        return True

    def action_help(self) -> None:
        self.show_help(self.screen)

    def show_help(self, screen: Screen[Any]) -> None:
        """The keys of ``screen`` (the one in view; the palette passes the one it was
        opened from)."""
        if not isinstance(screen, HelpScreen):
            self.push_screen(HelpScreen.of(screen))

    def get_system_commands(self, screen: Screen[Any]) -> Iterable[SystemCommand]:
        # Textual's, but its Quit: slopetui.tui.commands has one that says what quitting keeps
        for command in super().get_system_commands(screen):
            if command.title != "Quit":
                yield command

    # -- the store and the worker pool --

    def open_store(self) -> None:
        """Open (and migrate) the store off the UI thread; then attach to or start a pool."""
        url = self.db_url
        # the store module's open_store, not this method
        self.background.start(lambda: open_store(url), done=self._store_opened,
                              failed=self._store_open_failed, group="store", exclusive=True)

    def _store_opened(self, db: Database) -> None:
        self.db = db  # before the screen in view is told
        self.store_error = None
        self.refresh_active_screen()
        self.background.start(
            partial(marked_runs, db), group="marks", done=self._marks_read,
            failed=lambda exc: self.notify_text(f"could not read the marked runs: {exc}",
                                                severity="warning", timeout=8))
        if self.start_workers:
            self.background.start(
                partial(attach_pool, db), group="pool",
                done=lambda text: self.notify_text(text, timeout=6),
                failed=lambda exc: self.notify_text(f"could not start workers: {exc}",
                                                    severity="error", timeout=10))

    def _store_open_failed(self, exc: Exception) -> None:
        self.store_error = f"{type(exc).__name__}: {exc}"
        self.refresh_bindings()  # ctrl+o is active now
        self.action_store_dialog()

    @property
    def store_status(self) -> Text:
        """What a screen without a store says: that it is being opened, or why it could
        not be and how to try again. A Text: the cause may hold brackets."""
        if self.store_error is None:
            return Text(OPENING_STORE)
        return Text.assemble(("The store could not be opened: ", "bold"), self.store_error,
                             "\nctrl+o retries it or opens another store "
                             "(or ctrl+p: Retry opening the store).")

    def action_store_dialog(self) -> None:
        """Retry opening the store, open another one, or quit."""
        if self.store_error is not None and not isinstance(self.screen, StoreErrorScreen):
            self.push_screen(StoreErrorScreen(self.store_error), self._store_chosen)

    def _store_chosen(self, choice: StoreChoice | None) -> None:
        if choice is None:  # closed: the sweeps screen says how to come back
            self.refresh_active_screen()
            return
        if choice.action == "open":
            self.db_url = choice.url
        self.retry_store()

    def retry_store(self) -> None:
        """Open the store (db_url) again, e.g. once its folder exists."""
        if self.db is not None:
            return
        self.store_error = None
        self.refresh_bindings()
        self.refresh_active_screen()  # "Opening the store…" again
        self.open_store()

    def notify_text(self, text: str, **kwargs: Any) -> None:
        """A notification whose text may quote stored text, a database's message or a path:
        its control characters escaped (slopetui.display_text) and never read as markup (a
        bracket in a name or a path would be a tag)."""
        self.notify(terminal_safe_lines(text), markup=False, **kwargs)

    def refresh_active_screen(self) -> None:
        """Tell the screen in view that the store is open or has changed."""
        if isinstance(self.screen, SlopeScreen):  # not an error or the command palette
            self.screen.refresh_data()

    def control_sweep(self, action: str, sweep_id: int) -> None:
        """Pause, resume or cancel a sweep (from any screen), then refresh the view."""
        db = self.db

        def apply() -> str:
            if db is None:  # the screens offer the keys once the store is open
                raise RuntimeError("the database is not open yet")
            return control.apply(db, action, sweep_id)

        def done(text: str) -> None:
            self.notify_text(text)
            self.refresh_active_screen()

        self.background.start(
            apply, done=done, group="sweep-control",
            failed=lambda exc: self.notify_text(f"{action} sweep {sweep_id}: {exc}",
                                                severity="error", timeout=8))

    # -- screens pushed on top --

    async def action_quit(self) -> None:
        """Quit; on a screen that holds unsaved input (the new-sweep and analysis forms, a
        sweep's labels: ``unsaved``) ask first, naming what would be lost: ctrl+q threw a
        filled form away at once. A second ctrl+q, on the question, quits."""
        unsaved = getattr(self.screen, "unsaved", None)
        lost = unsaved() if callable(unsaved) else None
        if lost is None:
            self.exit()
            return
        self.push_screen(ConfirmScreen(f"Quit slopetui? {lost}", yes="Quit",
                                       no="Keep editing"),
                         lambda yes: self.exit() if yes else None)

    async def action_new_sweep(self) -> None:
        await self.new_sweep()

    async def new_sweep(self, preset: str | None = None) -> None:
        """The new-sweep form, filled with ``preset`` (a key of sweeps.presets) if given:
        choosing it in the form's preset list fills the fields, as a click would."""
        screen = NewSweepScreen()
        await self.push_screen(screen)  # mounted: its fields exist
        if preset is not None:
            screen.query_one("#preset", Select).value = preset

    # -- the analyses (slopetui.tui.screens.analyses) --

    def analysis_point(self) -> tuple[Params, str]:
        """Where the analyses open: the point of the screen in view (the diagram cursor's,
        a run's: its ``analysis_point``), else the paper's defaults; and a word on which."""
        for screen in reversed(self.screen_stack):
            point_of = getattr(screen, "analysis_point", None)
            found = point_of() if callable(point_of) else None
            if found is not None:
                return found
        return Params(), "the paper's defaults"

    def open_analysis(self, kind: str) -> None:
        """The form of one analysis: "continuation", "hysteresis" or "orbit", at
        analysis_point()."""
        at, where = self.analysis_point()
        form = {"continuation": analyses.continuation, "hysteresis": analyses.hysteresis,
                "orbit": analyses.orbit}[kind](at)
        self.push_screen(AnalysisFormScreen(form))
        self.notify_text(f"the form opens at {where}", timeout=4)

    def action_open_analysis(self, kind: str) -> None:
        self.open_analysis(kind)

    def certified_rerun(self, run_id: int) -> None:
        """The form that queues run ``run_id`` again with the certified stop."""
        self.push_screen(AnalysisFormScreen(analyses.rerun(self.db, run_id)))

    def open_run(self, run_id: int) -> None:
        from slopetui.tui.screens.run_detail import RunDetailScreen  # numba: module docstring
        self.push_screen(RunDetailScreen(run_id))

    # -- runs marked for comparison, figures and exports --

    def _marks_read(self, marks: tuple[int, ...]) -> None:
        # marks made before the read (the store is open by then: none) are kept after them
        self.marked = [*marks, *(r for r in self.marked if r not in marks)]

    def toggle_mark(self, run_id: int) -> None:
        """Mark a run for the compare screen, or unmark it; say what is marked. The store
        keeps the marks (written off the UI thread; the list here is what it holds)."""
        if run_id in self.marked:
            self.marked.remove(run_id)
            verb = "unmarked"
        else:
            self.marked.append(run_id)
            verb = "marked"
        listed = ", ".join(map(str, self.marked)) or "none"
        hint = "; v compares them" if len(self.marked) >= 2 else "; mark another to compare"
        self.notify(f"run {run_id} {verb} (marked: {listed}){hint}")
        if self.db is not None:
            db, wanted = self.db, run_id in self.marked
            self._write_marks(
                partial(set_mark, db, run_id, wanted),
                lambda exc: self.notify_text(
                    f"run {run_id} {verb} for this session only: the store did not keep it "
                    f"({exc})", severity="warning", timeout=8))

    def clear_marks(self) -> None:
        """Unmark every run, here and in the store."""
        self.marked = []
        self.notify("no run is marked now")
        if self.db is not None:
            self._write_marks(partial(clear_marks, self.db),
                              lambda exc: self.notify_text(f"could not clear the marks: {exc}",
                                                           severity="error"))

    def _write_marks(self, write: Callable[[], object],
                     failed: Callable[[Exception], None]) -> None:
        """Write the marks off the UI thread, one write after another in the order asked:
        m then m again must reach the store as mark then unmark, never the other way round
        (two threads at once commit in either order)."""
        self._mark_writes.append((write, failed))
        if len(self._mark_writes) == 1:  # none under way: this one starts now
            self._next_mark_write()

    def _next_mark_write(self) -> None:
        write, failed = self._mark_writes[0]

        def ended() -> None:
            self._mark_writes.popleft()
            if self._mark_writes:
                self._next_mark_write()

        def done(result: object) -> None:
            ended()
            if not self._mark_writes and isinstance(result, tuple):
                # the last write's list is the store's (another application's marks too)
                self.marked = list(result)

        def not_written(exc: Exception) -> None:
            ended()
            failed(exc)

        self.background.start(write, group="marks", done=done, failed=not_written)

    def action_compare(self) -> None:
        if len(self.marked) < 2:
            self.notify("mark two or more runs with m (in a diagram or a run's detail), "
                        "then press v", severity="warning")
            return
        from slopetui.tui.screens.compare import CompareScreen  # numba: module docstring
        self.push_screen(CompareScreen(self.marked))

    def write_sweep_figure(self, diagram: SweepDiagram) -> None:
        """Write the sweep's figure (its diagram, with the fold curve if computed)."""
        fold, folder, db = self.fold_curves.get(diagram.id), self.figure_folder, self.db
        self._write_figure(lambda: figure_writing.write_sweep_figure(
            diagram, fold, folder, () if db is None else sweep_engines(db, diagram.id)))

    def write_runs_figure(self, runs: Sequence[tuple[StoredRun, Traces]]) -> None:
        """Write the figure of runs already recomputed: one run's four panels, or the
        comparison of several."""
        pairs, folder = list(runs), self.figure_folder
        self._write_figure(lambda: figure_writing.write_runs_figure(pairs, folder))

    def _write_figure(self, write: Callable[[], list[Path]]) -> None:
        """Draw and write a figure in ``figure_folder`` off the UI thread
        (slopetui.tui.figure_writing); an unwritable folder, a full disk: shown."""
        self.background.start(
            write, group="figure",
            done=lambda paths: self.notify_text(figure_writing.written_text(paths), timeout=10),
            failed=lambda exc: self.notify_text(
                f"could not write the figure: {type(exc).__name__}: {exc}", severity="error",
                timeout=10))

    def export_sweep(self, sweep_id: int, fmt: str) -> None:
        """Write the sweep's runs as CSV or JSON (``slopetui export``'s formats) into a new
        file in ``figure_folder``, off the UI thread."""
        db, folder = self.db, self.figure_folder

        def export() -> export_files.Exported:
            if db is None:
                raise RuntimeError("the database is not open yet")
            return export_files.export_sweep(db, sweep_id, fmt, figure_writing.ready_folder(folder))

        # an unknown sweep, an unwritable folder: shown; a path may hold brackets
        self.background.start(
            export, group="export",
            done=lambda exported: self.notify_text(
                f"{exported.runs} runs of sweep {sweep_id} written to {exported.path}",
                timeout=10),
            failed=lambda exc: self.notify_text(
                f"could not export sweep {sweep_id}: {type(exc).__name__}: {exc}",
                severity="error", timeout=10))


def run_app(db_url: str | None = None, *, start_workers: bool = True) -> int:
    SlopeApp(db_url, start_workers=start_workers).run()
    return 0
