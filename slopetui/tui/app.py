"""The slopetui application: sweeps, new sweep, run detail, queue, SQL console and
continuations (branches).

``slopetui`` with no arguments opens it on the default database and starts a detached
local worker pool, or attaches to the one already running on this host. The pool lives
on after the application quits: queued work is never lost by quitting.

The app's thread workers (opening the store, the pool, pausing a sweep) report back as the
screens' do: with a message, handled on the UI thread.

Keys: the footer of every screen shows the app's two (? help, ctrl+q quit) besides the
screen's own; the others (1-4, n, v) are in the help (? or F1, generated from the
bindings) and in the command palette (ctrl+p, ``slopetui.tui.commands``), which also
takes what a key cannot (open run 12, new sweep from a preset, export a sweep).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from rich.text import Text
from textual import on, work
from textual.app import App, SystemCommand
from textual.binding import Binding
from textual.message import Message
from textual.screen import Screen
from textual.widget import AwaitMount
from textual.widgets import Select

from slopetui.display_text import terminal_safe_lines
from slopetui.store.database import Database
from slopetui.store.open import open_store
from slopetui.sweeps.fold_overlay import Curve
from slopetui.tui.commands import SlopeCommands
from slopetui.tui.screens.base import SlopeScreen
from slopetui.tui.screens.branches import BranchesScreen
from slopetui.tui.screens.error import StoreChoice, StoreErrorScreen
from slopetui.tui.screens.help import HelpScreen
from slopetui.tui.screens.queue import QueueScreen
from slopetui.tui.screens.sql import SqlScreen
from slopetui.tui.screens.sweeps import SweepsScreen

if TYPE_CHECKING:  # matplotlib is loaded by the first figure, not by the application
    from slopetui.figures.output import Drawing
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
        #: Runs marked with m for the compare screen (v), in the order marked.
        self.marked: list[int] = []
        #: Where the figure key (f) and the palette's exports write: the folder the
        #: application was started in.
        self.figure_folder = Path.cwd()
        #: Why the store could not be opened (None: it is open, or being opened).
        self.store_error: str | None = None
        #: The modes whose screen is built (the default one from the start), and whether
        #: the switch under way goes to one of them (``switch_mode``).
        self._built_modes = {self.DEFAULT_MODE}
        self._switching_to_built = False

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

    # -- messages from the app's workers --

    @dataclass
    class StoreOpened(Message):
        db: Database

    @dataclass
    class StoreOpenFailed(Message):
        cause: str

    @dataclass
    class PoolAttached(Message):
        """Attached to this host's worker pool, or started one: what to tell the user."""

        text: str

    @dataclass
    class PoolFailed(Message):
        cause: str

    @dataclass
    class SweepControlled(Message):
        """A sweep was paused, resumed or cancelled: ``text`` says so (control.apply)."""

        text: str

    @dataclass
    class SweepControlFailed(Message):
        action: str
        sweep_id: int
        cause: str

    @dataclass
    class FigureWritten(Message):
        paths: list[Path]

    @dataclass
    class FigureFailed(Message):
        cause: str

    @dataclass
    class SweepExported(Message):
        text: str

    @dataclass
    class ExportFailed(Message):
        sweep_id: int
        cause: str

    def on_mount(self) -> None:
        self.open_store()

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

    @work(thread=True, exclusive=True, group="store")
    def open_store(self) -> None:
        """Open (and migrate) the store off the UI thread; then attach to or start a pool."""
        try:
            db = open_store(self.db_url)  # the store module's function, not this method
        except Exception as exc:  # any failure to open is shown, never a traceback
            self.post_message(self.StoreOpenFailed(f"{type(exc).__name__}: {exc}"))
            return
        self.post_message(self.StoreOpened(db))
        if self.start_workers:
            self.attach_pool(db)

    def attach_pool(self, db: Database) -> None:
        """In the store's worker: find or start the pool (it may take a few seconds)."""
        from slopetui.queue.defaults import IDLE_GRACE_S
        from slopetui.queue.local_pool import local_pools, start_detached_pool, store_key
        from slopetui.queue.open_apps import record_app
        try:
            # open on this store: a pool another application started stays while it is
            record_app(store_key(db.url.render_as_string(hide_password=False)), os.getpid())
            pools, _ = local_pools(db)  # a pool still warming up has no workers yet
            if pools:
                n = sum(len(p.workers) for p in pools)
                message = (f"attached to the worker pool of this host (pid "
                           f"{', '.join(str(p.pid) for p in pools)}, {n} workers)")
            else:
                # its owner is this process: it leaves once the application has quit and
                # the store has been idle for the grace period (slopetui.queue.idle_exit)
                pid, log = start_detached_pool(db, extra=("--owner-pid", str(os.getpid())))
                message = (f"worker pool started (pid {pid}, log {log}); after you quit it "
                           f"finishes the queue, then leaves once the store has been idle "
                           f"for {IDLE_GRACE_S:g} s")
        except Exception as exc:
            self.post_message(self.PoolFailed(str(exc)))
            return
        self.post_message(self.PoolAttached(message))

    @on(StoreOpened)
    def _store_opened(self, message: StoreOpened) -> None:
        self.db = message.db  # on the UI thread, before the screen in view is told
        self.store_error = None
        self.refresh_active_screen()

    @on(StoreOpenFailed)
    def _store_open_failed(self, message: StoreOpenFailed) -> None:
        self.store_error = message.cause
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

    @on(PoolAttached)
    def _pool_attached(self, message: PoolAttached) -> None:
        self.notify_text(message.text, timeout=6)

    @on(PoolFailed)
    def _pool_failed(self, message: PoolFailed) -> None:
        self.notify_text(f"could not start workers: {message.cause}", severity="error", timeout=10)

    def notify_text(self, text: str, **kwargs: Any) -> None:
        """A notification whose text may quote stored text, a database's message or a path:
        its control characters escaped (slopetui.display_text) and never read as markup (a
        bracket in a name or a path would be a tag)."""
        self.notify(terminal_safe_lines(text), markup=False, **kwargs)

    def refresh_active_screen(self) -> None:
        """Tell the screen in view that the store is open or has changed."""
        if isinstance(self.screen, SlopeScreen):  # not an error or the command palette
            self.screen.refresh_data()

    @work(thread=True, group="sweep-control")
    def control_sweep(self, action: str, sweep_id: int) -> None:
        """Pause, resume or cancel a sweep (from any screen), then refresh the view."""
        from slopetui.sweeps import control
        try:
            if self.db is None:  # the screens offer the keys once the store is open
                raise RuntimeError("the database is not open yet")
            text = control.apply(self.db, action, sweep_id)
        except Exception as exc:
            self.post_message(self.SweepControlFailed(action, sweep_id, str(exc)))
            return
        self.post_message(self.SweepControlled(text))

    @on(SweepControlled)
    def _sweep_controlled(self, message: SweepControlled) -> None:
        self.notify_text(message.text)
        self.refresh_active_screen()

    @on(SweepControlFailed)
    def _sweep_control_failed(self, message: SweepControlFailed) -> None:
        self.notify_text(f"{message.action} sweep {message.sweep_id}: {message.cause}",
                         severity="error", timeout=8)

    async def action_new_sweep(self) -> None:
        await self.new_sweep()

    async def new_sweep(self, preset: str | None = None) -> None:
        """The new-sweep form, filled with ``preset`` (a key of sweeps.presets) if given:
        choosing it in the form's preset list fills the fields, as a click would."""
        from slopetui.tui.screens.new_sweep import NewSweepScreen
        screen = NewSweepScreen()
        await self.push_screen(screen)  # mounted: its fields exist
        if preset is not None:
            screen.query_one("#preset", Select).value = preset

    def open_run(self, run_id: int) -> None:
        from slopetui.tui.screens.run_detail import RunDetailScreen
        self.push_screen(RunDetailScreen(run_id))

    # -- runs marked for comparison, and figures --

    def toggle_mark(self, run_id: int) -> None:
        """Mark a run for the compare screen, or unmark it; say what is marked."""
        if run_id in self.marked:
            self.marked.remove(run_id)
            verb = "unmarked"
        else:
            self.marked.append(run_id)
            verb = "marked"
        listed = ", ".join(map(str, self.marked)) or "none"
        hint = "; v compares them" if len(self.marked) >= 2 else "; mark another to compare"
        self.notify(f"run {run_id} {verb} (marked: {listed}){hint}")

    def action_compare(self) -> None:
        if len(self.marked) < 2:
            self.notify("mark two or more runs with m (in a diagram or a run's detail), "
                        "then press v", severity="warning")
            return
        from slopetui.tui.screens.compare import CompareScreen
        self.push_screen(CompareScreen(self.marked))

    def write_sweep_figure(self, diagram: SweepDiagram) -> None:
        """Write the sweep's figure (its diagram, with the fold curve if computed)."""
        from slopetui.figures.figure_files import sweep_figure, sweep_stem
        fold = self.fold_curves.get(diagram.id)
        self.write_figure(lambda: sweep_figure(diagram, fold=fold), sweep_stem(diagram.id))

    def write_runs_figure(self, runs: Sequence[tuple[StoredRun, Traces]]) -> None:
        """Write the figure of runs already recomputed: one run's four panels, or the
        comparison of several."""
        from slopetui.figures.figure_files import runs_stem
        from slopetui.figures.run_figure import run_drawing
        pairs = list(runs)
        self.write_figure(lambda: run_drawing(pairs), runs_stem([r.id for r, _ in pairs]))

    @work(thread=True, group="figure")
    def write_figure(self, make: Callable[[], Drawing], stem: str) -> None:
        """Draw and write a figure off the UI thread (matplotlib takes ~1 s to load and
        a second or two to draw), under a name not yet taken in ``figure_folder``."""
        from slopetui.figures.figure_files import unused_path
        from slopetui.figures.output import write
        try:
            paths = write(make(), unused_path(self.figure_folder, stem))
        except Exception as exc:  # an unwritable folder, a full disk: shown, never a traceback
            self.post_message(self.FigureFailed(f"{type(exc).__name__}: {exc}"))
            return
        self.post_message(self.FigureWritten(paths))

    @on(FigureWritten)
    def _figure_written(self, message: FigureWritten) -> None:
        figure, *data = message.paths
        beside = f" (its data: {', '.join(p.name for p in data)})" if data else ""
        self.notify_text(f"figure written: {figure}{beside}", timeout=10)

    @on(FigureFailed)
    def _figure_failed(self, message: FigureFailed) -> None:
        self.notify_text(f"could not write the figure: {message.cause}", severity="error", timeout=10)

    @work(thread=True, group="export")
    def export_sweep(self, sweep_id: int, fmt: str) -> None:
        """Write the sweep's runs as CSV or JSON (``slopetui export``'s formats) into a new
        file in ``figure_folder``, off the UI thread."""
        from slopetui.sweeps.export_files import export_sweep
        try:
            if self.db is None:
                raise RuntimeError("the database is not open yet")
            exported = export_sweep(self.db, sweep_id, fmt, self.figure_folder)
        except Exception as exc:  # an unknown sweep, an unwritable folder: shown
            self.post_message(self.ExportFailed(sweep_id, f"{type(exc).__name__}: {exc}"))
            return
        self.post_message(self.SweepExported(
            f"{exported.runs} runs of sweep {sweep_id} written to {exported.path}"))

    @on(SweepExported)
    def _sweep_exported(self, message: SweepExported) -> None:
        self.notify_text(message.text, timeout=10)  # a path may hold brackets

    @on(ExportFailed)
    def _export_failed(self, message: ExportFailed) -> None:
        self.notify_text(f"could not export sweep {message.sweep_id}: {message.cause}",
                         severity="error", timeout=10)


def run_app(db_url: str | None = None, *, start_workers: bool = True) -> int:
    SlopeApp(db_url, start_workers=start_workers).run()
    return 0
