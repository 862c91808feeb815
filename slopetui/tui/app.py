"""The slopetui application: sweeps, new sweep, run detail, queue, SQL console and
continuations (branches).

``slopetui`` with no arguments opens it on the default database and starts a detached
local worker pool, or attaches to the one already running on this host. The pool lives
on after the application quits: queued work is never lost by quitting.

The app's thread workers (opening the store, the pool, pausing a sweep) report back as the
screens' do: with a message, handled on the UI thread.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from textual import on, work
from textual.app import App
from textual.binding import Binding
from textual.message import Message

from slopetui.store.database import Database
from slopetui.store.open import open_store
from slopetui.sweeps.fold_overlay import Curve
from slopetui.tui.screens.base import SlopeScreen
from slopetui.tui.screens.branches import BranchesScreen
from slopetui.tui.screens.error import ErrorScreen
from slopetui.tui.screens.queue import QueueScreen
from slopetui.tui.screens.sql import SqlScreen
from slopetui.tui.screens.sweeps import SweepsScreen

if TYPE_CHECKING:  # matplotlib is loaded by the first figure, not by the application
    from slopetui.figures.output import Drawing
    from slopetui.sweeps.diagram import SweepDiagram
    from slopetui.sweeps.recompute import StoredRun, Traces

#: Seconds between refreshes of the live views (progress, diagrams, workers).
REFRESH_S = 2.0


class SlopeApp(App[None]):
    """The researcher's cockpit over one store."""

    CSS_PATH = "slopetui.tcss"
    TITLE = "slopetui"
    SUB_TITLE = "mean-field spring-block landslide model"
    MODES = {"sweeps": SweepsScreen, "queue": QueueScreen, "sql": SqlScreen,
             "branches": BranchesScreen}
    DEFAULT_MODE = "sweeps"
    BINDINGS = [
        Binding("1", "switch_mode('sweeps')", "Sweeps", id="mode.sweeps"),
        Binding("2", "switch_mode('queue')", "Queue", id="mode.queue"),
        Binding("3", "switch_mode('sql')", "SQL", id="mode.sql"),
        Binding("4", "switch_mode('branches')", "Branches", id="mode.branches"),
        Binding("n", "new_sweep", "New sweep", id="new_sweep"),
        # out of the footer (80 columns hold no more): marking a run says "v compares them"
        Binding("v", "compare", "Compare", id="compare", show=False),
        Binding("q", "quit", "Quit", id="quit"),
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
        #: Where the figure key (f) writes: the folder the application was started in.
        self.figure_folder = Path.cwd()

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

    def on_mount(self) -> None:
        self.open_store()

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
        from slopetui.queue.local_pool import local_pools, start_detached_pool
        try:
            pools, _ = local_pools(db)  # a pool still warming up has no workers yet
            if pools:
                n = sum(len(p.workers) for p in pools)
                message = (f"attached to the worker pool of this host (pid "
                           f"{', '.join(str(p.pid) for p in pools)}, {n} workers)")
            else:
                pid, log = start_detached_pool(db)
                message = f"worker pool started (pid {pid}, log {log}); it keeps running after you quit"
        except Exception as exc:
            self.post_message(self.PoolFailed(str(exc)))
            return
        self.post_message(self.PoolAttached(message))

    @on(StoreOpened)
    def _store_opened(self, message: StoreOpened) -> None:
        self.db = message.db  # on the UI thread, before the screen in view is told
        self.refresh_active_screen()

    @on(StoreOpenFailed)
    def _store_open_failed(self, message: StoreOpenFailed) -> None:
        self.push_screen(ErrorScreen("The database cannot be opened", message.cause))

    @on(PoolAttached)
    def _pool_attached(self, message: PoolAttached) -> None:
        self.notify(message.text, timeout=6)

    @on(PoolFailed)
    def _pool_failed(self, message: PoolFailed) -> None:
        self.notify(f"could not start workers: {message.cause}", severity="error", timeout=10)

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
        self.notify(message.text)
        self.refresh_active_screen()

    @on(SweepControlFailed)
    def _sweep_control_failed(self, message: SweepControlFailed) -> None:
        self.notify(f"{message.action} sweep {message.sweep_id}: {message.cause}",
                    severity="error", timeout=8)

    def action_new_sweep(self) -> None:
        from slopetui.tui.screens.new_sweep import NewSweepScreen
        self.push_screen(NewSweepScreen())

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
        self.notify(f"figure written: {figure}{beside}", timeout=10)

    @on(FigureFailed)
    def _figure_failed(self, message: FigureFailed) -> None:
        self.notify(f"could not write the figure: {message.cause}", severity="error", timeout=10)


def run_app(db_url: str | None = None, *, start_workers: bool = True) -> int:
    SlopeApp(db_url, start_workers=start_workers).run()
    return 0
