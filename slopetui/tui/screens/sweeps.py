"""Sweeps: the list with progress, and the selected sweep's diagram filling live; over a
(k, tau) phase diagram (or (a|b|c, tau)), on request, the fold of cycles (key o).

Cancel (c) and delete (x) ask first, in a modal naming the sweep and what it would touch
(``screens.confirm``); pause and resume do not: each undoes the other, and resume also
undoes a cancel (its cancelled runs are queued again, ``sweeps.control``).

The progress bar shows each kind of run for what it is: done green, failed red, cancelled
dim yellow, left grey, in distinct characters too (█ ▓ ▒ ░) for a terminal without colour
(NO_COLOR); its percentage counts done runs only. A sweep whose runs all failed is a red
bar at 0%, not a full green one.

The name column takes the width the other columns leave (at least NAME_MIN), computed
anew on every refresh and resize from the screen's width.

The keys act on the sweep the list highlights, and only its diagram is ever on show: a
sweep selected shows at once its diagram as last read, or a line saying it is being read,
never the diagram of the sweep selected before (d, a click or the arrows went into that one
while a large sweep was read, and x named a sweep the user had not meant); a refresh that
refills the list keeps its cursor on the row the user moved it to.

The selected sweep's diagram is read whole once, then only what changed
(``sweeps.live_diagram``), every refresh while the screen is in view and never while
another covers it (``SlopeScreen.refresh_while_shown``); the grid is rebuilt and drawn
again only when a run changed. A 10,000-run sweep cost a whole read and a redraw every
2 s, 0.3 s of a loaded core each, behind every other screen too.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import accumulate, pairwise
from typing import Any

from rich.text import Text
from textual import events, on, work
from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Vertical
from textual.message import Message
from textual.widgets import ContentSwitcher, DataTable, Header, Static
from textual.worker import get_current_worker

from core.params import Params
from slopetui.display_text import terminal_safe
from slopetui.duration_text import duration_text
from slopetui.sweeps import fold_overlay
from slopetui.sweeps.control import EXPLAINED, UnknownSweep
from slopetui.sweeps.diagram import RunPoint, SweepDiagram, plane_hopf
from slopetui.sweeps.hopf_plane import Curve
from slopetui.sweeps.initial_dependence import condition_notes, drawn
from slopetui.sweeps.live_diagram import LiveDiagram
from slopetui.sweeps.progress import SweepProgress, sweep_progress
from slopetui.sweeps.spec import SweepSpec
from slopetui.tui import garbage
from slopetui.tui.messages import RunChosen, RunMarked, StoreFailed
from slopetui.tui.screens.base import SlopeScreen
from slopetui.tui.screens.confirm import ask_then_control
from slopetui.tui.screens.sweep_labels import edit_labels
from slopetui.tui.widgets.bifurcation_view import BifurcationView
from slopetui.tui.widgets.phase_grid import GridData, PhaseGrid, cell_label
from slopetui.tui.widgets.steady_footer import SteadyFooter

BAR_WIDTH = 10
#: Names are cut to the width the other columns leave, but never to fewer characters than
#: this (at 80 columns the table is then a little wider than the screen, as before).
NAME_MIN = 20
#: The bar's cells: done, failed, cancelled, left. Distinct characters as well as colours,
#: so that the bar reads the same without colour (NO_COLOR, a monochrome terminal).
BAR_CELLS = (("█", "green"), ("▓", "red"), ("▒", "yellow dim"), ("░", "bright_black"))
#: The table's columns, in order; the name is the one that takes the room left.
COLUMNS = ("id", "name", "progress", "done", "r/min", "ETA", "status")
NAME_COLUMN = COLUMNS.index("name")


def bar_cells(total: int, done: int, failed: int = 0, cancelled: int = 0) -> list[int]:
    """How many of the BAR_WIDTH cells are done, failed, cancelled and left. Cumulative
    rounding keeps the four at BAR_WIDTH; a failed or cancelled run, however few, takes at
    least one cell (from the largest other part): what went wrong stays visible."""
    counts = [done, failed, cancelled]
    bounds = [round(BAR_WIDTH * min(n, total) / total) if total else 0
              for n in accumulate(counts, initial=0)]
    cells = [b - a for a, b in pairwise(bounds)]
    cells.append(BAR_WIDTH - bounds[-1])
    for i in (1, 2):
        if counts[i] and not cells[i]:
            donor = max((j for j in range(4) if j != i), key=lambda j: cells[j])
            if cells[donor] > 1 or (donor == 3 and cells[donor]):
                cells[donor] -= 1
                cells[i] += 1
    return cells


def progress_bar(done: int, total: int, failed: int = 0, cancelled: int = 0) -> Text:
    """The bar and the share of runs done (failed and cancelled runs are not done)."""
    cells = bar_cells(total, done, failed, cancelled)
    return Text.assemble(*((char * n, style) for (char, style), n in zip(BAR_CELLS, cells,
                                                                          strict=True)),
                         f" {100 * done // max(total, 1):>3}%")


def grid_data(d: SweepDiagram, hopf: Curve | None, fold: Curve | None = None) -> GridData:
    spec = d.spec
    assert spec.y is not None
    x, y = spec.x, spec.y
    shown = drawn(d)  # several initial conditions: their map (sweeps.initial_dependence)
    # labels, not bare regimes: a failed or cancelled run has none and is not pending
    runs = {(r.ix, r.iy): (r.id, cell_label(r.regime, r.status)) for r in shown.runs}
    return GridData(x.param, y.param, x.values(), y.values(), x.spacing == "log",
                    y.spacing == "log", runs, hopf,
                    frozenset((r.ix, r.iy) for r in shown.runs if r.inferred),
                    spec.adaptive_levels is not None, fold, condition_notes(d))


class FoldCancelled(Exception):
    """The fold's worker was cancelled (the app quits): stop between two values of tau,
    not minutes later."""


class SweepsScreen(SlopeScreen[None]):
    """Enter on a sweep moves to its diagram; arrows move the cursor there, enter opens
    the run under it, m marks it for comparison (v); f writes the diagram's figure."""

    # The footer shows five, in about 45 columns (the app adds its own few at 80); the
    # others are in the help screen and the command palette.
    BINDINGS = [
        Binding("p", "pause", "Pause", id="sweeps.pause",
                tooltip=EXPLAINED["pause"]),
        Binding("r", "resume", "Resume", id="sweeps.resume",
                tooltip=EXPLAINED["resume"]),
        Binding("c", "cancel", "Cancel", id="sweeps.cancel",
                tooltip=EXPLAINED["cancel"]),
        Binding("f", "figure", "Figure", id="sweeps.figure",
                tooltip="Write the shown diagram's figure (as slopetui figure SWEEP)"),
        Binding("o", "fold_curve", "Fold", id="sweeps.fold",
                tooltip="Draw the fold of cycles over a (k, tau) phase diagram"),
        Binding("d", "focus_diagram", "Diagram", id="sweeps.diagram", show=False,
                tooltip="Move to the diagram: arrows move, enter opens a run, m marks it"),
        Binding("x", "delete", "Delete sweep", id="sweeps.delete", show=False,
                tooltip=EXPLAINED["delete"]),
        Binding("e", "labels", "Name, tags, note", id="sweeps.labels", show=False,
                tooltip="Rename the selected sweep, tag it, write its note "
                        "(as slopetui rename, tag, note)"),
        Binding("escape", "focus_list", "Sweep list", show=False),
    ]

    @dataclass
    class Loaded(Message):
        sweeps: list[SweepProgress]
        diagram: SweepDiagram | None
        grid: GridData | None  # for a 2-D sweep (the same object while nothing changed)

    @dataclass
    class FoldProgress(Message):
        """The fold of cycles was looked for at one more tau: ``fold`` is the value of
        ``param`` (the plane's x) there, None if there is none."""

        sweep_id: int
        param: str
        done: int
        total: int
        tau: float
        fold: float | None

    @dataclass
    class FoldComputed(Message):
        sweep_id: int
        curve: Curve

    @dataclass
    class FoldFailed(Message):
        sweep_id: int
        cause: str

    def __init__(self) -> None:
        super().__init__()
        self.selected: int | None = None
        #: Hopf curves by sweep id: a spec never changes, and the curve costs ~0.1 s.
        self._hopf: dict[int, Curve | None] = {}
        #: The diagram on show (its spec says whether a fold curve applies).
        self._shown: SweepDiagram | None = None
        #: The sweep whose fold curve is being computed, and how far it got (tau done, of).
        self._fold_for: int | None = None
        self._fold_done: tuple[int, int] = (0, 0)
        #: The sweeps as last loaded (the confirmations name them; a resize refills).
        self._sweeps: list[SweepProgress] = []
        #: The sweeps the table shows (None: not filled yet).
        self._listed: list[SweepProgress] | None = None
        #: Each sweep's diagram as read so far (live_diagram), and the grid last made of
        #: it with the fold curve it was made with, by id: the load worker's.
        self._live: dict[int, LiveDiagram] = {}
        self._grids: dict[int, tuple[SweepDiagram, Curve | None, GridData]] = {}
        #: The grid on show (the same object again: nothing to draw anew).
        self._shown_grid: GridData | None = None
        #: Each sweep's diagram and grid as last shown, by id (the UI thread's): shown at
        #: once when the sweep is selected again, while its load brings it up to date.
        self._seen: dict[int, tuple[SweepDiagram, GridData | None]] = {}

    def compose(self) -> ComposeResult:
        yield Header()
        table: DataTable[Any] = DataTable(id="sweep-table", cursor_type="row", zebra_stripes=True)
        table.add_columns(*COLUMNS)
        yield table
        with Vertical(id="diagram-pane"):
            with ContentSwitcher(initial="diagram-empty", id="diagram-switcher"):
                yield Static("Opening the store…", id="diagram-empty")
                yield PhaseGrid(id="phase-grid")
                yield BifurcationView(id="bifurcation")
        yield SteadyFooter()

    def on_mount(self) -> None:
        self.refresh_while_shown()

    def refresh_data(self) -> None:
        if self.hidden:  # read once shown again (SlopeScreen._resume_refresh)
            return
        if self.db is not None:
            self.load(self.selected)
        else:  # the store is being opened, or could not be: say which, and how to retry
            self.query_one("#diagram-empty", Static).update(self.app.store_status)

    @work(thread=True, exclusive=True, group="sweeps-load")
    def load(self, sweep_id: int | None) -> None:
        db = self.db
        if db is None:  # refresh_data starts this once the store is open
            return
        try:
            sweeps = sweep_progress(db)
            ids = {p.id for p in sweeps}
            for gone in set(self._live) - ids:  # deleted (pop: an older load may race)
                self._live.pop(gone, None)
                self._grids.pop(gone, None)
            if sweep_id not in ids:  # none yet, or it was deleted
                sweep_id = sweeps[0].id if sweeps else None
            diagram = base = None
            changes: list[RunPoint] = []
            if sweep_id is not None:
                live = self._live.setdefault(sweep_id, LiveDiagram(sweep_id))
                live.refresh(db)
                diagram, base, changes = live.state()
        except UnknownSweep:  # deleted since sweep_progress read it: the next load says so
            return
        except Exception as exc:  # a locked or vanished database: say so, keep running
            self.post_message(StoreFailed("read the sweeps", f"{type(exc).__name__}: {exc}"))
            return
        grid = None
        if diagram is not None and diagram.spec.y is not None:
            grid = self._grid_of(diagram, base, changes)
        self.post_message(self.Loaded(sweeps, diagram, grid))

    def _grid_of(self, diagram: SweepDiagram, base: SweepDiagram | None,
                 changes: list[RunPoint]) -> GridData:
        """The grid of the diagram (in the load worker): the one made before if nothing
        changed, that one with the changed runs put in if it was made from the diagram
        they changed (``base``; one initial condition: a cell is its run), else made
        anew."""
        fold = self.app.fold_curves.get(diagram.id)
        made = self._grids.get(diagram.id)
        if made is not None and made[1] is fold:
            if made[0] is diagram:
                return made[2]  # nothing changed: the grid made before, drawn already
            if made[0] is base and len(diagram.spec.conditions) < 2:
                grid = made[2].with_runs({(r.ix, r.iy): (r.id, cell_label(r.regime, r.status),
                                                         r.inferred) for r in changes})
                self._grids[diagram.id] = (diagram, fold, grid)
                return grid
        if diagram.id not in self._hopf:
            self._hopf[diagram.id] = plane_hopf(diagram.spec)
        grid = grid_data(diagram, self._hopf[diagram.id], fold)
        self._grids[diagram.id] = (diagram, fold, grid)
        return grid

    def on_sweeps_screen_loaded(self, message: Loaded) -> None:
        ids = [p.id for p in message.sweeps]
        for gone in set(self._seen) - set(ids):
            del self._seen[gone]
        if self.selected not in ids:  # none yet, or deleted: the one load() fell back to
            self.selected = message.diagram.id if message.diagram is not None else None
        if message.sweeps != self._listed:  # a table refilled is drawn again
            self._sweeps = self._listed = message.sweeps
            self._fill_table()
        if message.diagram is not None and message.diagram.id != self.selected:
            # the load of a sweep selected before: load() is exclusive, but a worker it
            # replaced still posts what it read; the selected sweep's load follows
            return
        if message.diagram is self._shown and message.grid is self._shown_grid:
            return  # nothing changed: no redraw
        if self._shown is None and message.diagram is not None:  # the first diagram
            self.call_after_refresh(garbage.settle)
        self._shown, self._shown_grid = message.diagram, message.grid
        if message.diagram is not None:
            self._seen[message.diagram.id] = (message.diagram, message.grid)
        self._show_diagram(message.diagram, message.grid)

    def on_resize(self, event: events.Resize) -> None:
        if self._sweeps:  # the name column's width follows the screen's
            self._fill_table()

    @staticmethod
    def _row(p: SweepProgress) -> list[Text]:
        """The row of a sweep, its name not yet cut to the column."""
        # stored text: escaped (control characters) and a Text (a str cell would be read
        # as markup: "[bold red]x" styled, "[/x]" a MarkupError that stops the screen)
        status = terminal_safe(p.status)
        status = f"{status}, {p.failed} failed" if p.failed else status
        if p.adaptive_levels is not None and not p.refined:  # short: fits 80 columns
            status += f", L{p.level}/{p.adaptive_levels}"
        return [Text(str(p.id)), Text(terminal_safe(p.name)),
                progress_bar(p.done, p.total, p.failed, p.cancelled),
                Text(f"{p.done}/{p.total}"), Text(f"{p.runs_per_min:.0f}"),
                Text(duration_text(p.eta_s)), Text(status)]

    def _fill_table(self) -> None:
        table = self.query_one("#sweep-table", DataTable)
        sweeps = self._sweeps
        rows = [self._row(p) for p in sweeps]
        # Every column as wide as its widest cell; the name as wide as the room the others
        # leave (the scrollbar's gutter kept free), at least NAME_MIN: set each time, as an
        # auto-width column never narrows again after a resize.
        widths = [max([len(label), *(row[i].cell_len for row in rows)])
                  for i, label in enumerate(COLUMNS)]
        others = sum(w for i, w in enumerate(widths) if i != NAME_COLUMN)
        room = (self.size.width - 2 * table.cell_padding * len(COLUMNS) - others
                - table.styles.scrollbar_size_vertical)
        name_width = max(NAME_MIN, room)
        widths[NAME_COLUMN] = min(widths[NAME_COLUMN], name_width)
        for column, width in zip(table.columns.values(), widths, strict=True):
            column.auto_width, column.width = False, width
        keep = table.cursor_row
        # The row the user moved the cursor to: its highlight may not be handled yet (a
        # refresh read before the key landed first), and is then the selection to come.
        moved = (int(table.coordinate_to_cell_key(table.cursor_coordinate).row_key.value or 0)
                 if table.row_count else None)
        # Refilled without RowHighlighted: putting the cursor back on the selected sweep
        # is no choice of the user's. clear() puts the cursor on row 0, the first row
        # added is announced as highlighted, then the selected one by move_cursor;
        # _row_highlighted took the first for a choice: it selected and loaded the first
        # sweep (drawing its diagram), then the selected one again. With any sweep but the
        # first selected, every refill thus started two loads, whose sweeps differ from
        # the last ones (runs per minute depend on the time): another refill, and so on,
        # dozens a second, a whole core on an idle screen.
        with table.prevent(DataTable.RowHighlighted):
            table.clear()
            for p, row in zip(sweeps, rows, strict=True):
                name = row[NAME_COLUMN]
                if name.cell_len > name_width:
                    name.truncate(name_width - 1)
                    name.append("…")
                table.add_row(*row, key=str(p.id))
            if sweeps:
                ids = [p.id for p in sweeps]
                at = (ids.index(moved) if moved in ids
                      else ids.index(self.selected) if self.selected in ids
                      else min(keep, len(ids) - 1))
                table.move_cursor(row=at, animate=False)
        if not sweeps:
            self.query_one("#diagram-empty", Static).update(
                "No sweeps yet: press n to design one (or slopetui submit).")

    def _show_diagram(self, diagram: SweepDiagram | None, grid: GridData | None) -> None:
        switcher = self.query_one("#diagram-switcher", ContentSwitcher)
        if diagram is None:
            switcher.current = "diagram-empty"
        elif diagram.spec.y is None:
            self.query_one(BifurcationView).set_diagram(diagram)
            switcher.current = "bifurcation"
        else:
            phase_grid = self.query_one(PhaseGrid)
            if grid is not phase_grid.data:  # the same grid again: drawn already
                phase_grid.set_data(grid)
            switcher.current = "phase-grid"
        focused = self.focused
        if isinstance(focused, (PhaseGrid, BifurcationView)) and focused.id != switcher.current:
            # the keys never stay with a diagram put away: the one on show, or the list
            self.query_one(f"#{switcher.current}" if diagram is not None
                           else "#sweep-table").focus()

    def _select(self, sweep_id: int) -> None:
        """Select a sweep: its diagram as last read (or a line saying it is being read)
        replaces the one on show at once, and a load brings it up to date."""
        self.selected = sweep_id
        seen = self._seen.get(sweep_id)
        self._shown, self._shown_grid = seen or (None, None)
        if seen is None:
            self.query_one("#diagram-empty", Static).update(
                f"Reading the diagram of sweep {sweep_id}…")
        self._show_diagram(*(seen or (None, None)))
        self.refresh_data()

    @on(DataTable.RowHighlighted, "#sweep-table")
    def _row_highlighted(self, event: DataTable.RowHighlighted) -> None:
        if event.row_key.value is not None:
            chosen = int(event.row_key.value)
            if chosen != self.selected:
                self._select(chosen)

    @on(DataTable.RowSelected, "#sweep-table")
    def _row_selected(self) -> None:
        self.action_focus_diagram()

    def action_focus_diagram(self) -> None:
        current = self.query_one("#diagram-switcher", ContentSwitcher).current
        if current in ("phase-grid", "bifurcation"):  # the selected sweep's (_select)
            self.query_one(f"#{current}").focus()
        elif self.selected is not None and self.db is not None:
            self.notify(f"the diagram of sweep {self.selected} is still being read")

    def action_focus_list(self) -> None:
        grid = self.query_one(PhaseGrid)
        if grid.full:  # the list is hidden at full resolution: back to the whole diagram
            grid.action_zoom()
        self.query_one("#sweep-table").focus()

    @on(PhaseGrid.Zoomed)
    def _zoomed(self, message: PhaseGrid.Zoomed) -> None:
        # at full resolution the list gives its lines to the diagram (slopetui.tcss)
        self.set_class(message.full, "-zoomed")

    def analysis_point(self) -> tuple[Params, str] | None:
        """Where an analysis opened from here starts (SlopeApp.analysis_point): the phase
        diagram cursor's point (the sweep's fixed values, the cursor's x and y), else the
        selected sweep's fixed values; None with no sweep on show."""
        shown = self._shown
        if shown is None:
            return None
        spec = shown.spec
        at = self.query_one(PhaseGrid).cursor_run() if spec.y is not None else None
        if at is None or spec.y is None:
            return spec.base, f"sweep {shown.id}'s fixed values"
        _run_id, x, y, _label = at
        return (spec.base.with_(**{spec.x.param: x, spec.y.param: y}),
                f"the cursor's point, {spec.x.param} = {x:g}, {spec.y.param} = {y:g}")

    @on(RunChosen)
    def _open_run(self, message: RunChosen) -> None:
        self.app.open_run(message.run_id)

    @on(RunMarked)
    def _mark_run(self, message: RunMarked) -> None:
        self.app.toggle_mark(message.run_id)

    def action_figure(self) -> None:
        """Write the shown sweep's figure (slopetui figure SWEEP) and say where."""
        if self._shown is None:
            self.notify("no sweep to draw", severity="warning")
            return
        self.notify(f"drawing the figure of sweep {self._shown.id}…")
        self.app.write_sweep_figure(self._shown)

    def _control(self, action: str) -> None:
        if self.selected is not None and self.db is not None:
            self.app.control_sweep(action, self.selected)

    def _selected_sweep(self) -> SweepProgress | None:
        if self.db is None:
            return None
        return next((p for p in self._sweeps if p.id == self.selected), None)

    def action_pause(self) -> None:
        self._control("pause")

    def action_resume(self) -> None:
        self._control("resume")

    def action_cancel(self) -> None:
        """Cancel the selected sweep's queued runs, once the modal says yes."""
        p = self._selected_sweep()
        if p is not None:
            ask_then_control(self.app, "cancel", p)

    def action_labels(self) -> None:
        """The selected sweep's name, tags and note, in a modal (screens.sweep_labels)."""
        p = self._selected_sweep()
        if p is None:
            self.notify("no sweep selected", severity="warning")
        else:
            edit_labels(self.app, p.id)

    def action_delete(self) -> None:
        """Delete the selected sweep and its runs, once the modal says yes."""
        p = self._selected_sweep()
        if p is None:
            self.notify("no sweep to delete", severity="warning")
        elif p.running:  # the store would refuse: say so now rather than after a yes
            self.notify(f"sweep {p.id} has {p.running} running runs: cancel it (c), wait "
                        "for them to finish, then delete it", severity="warning", timeout=8)
        else:
            ask_then_control(self.app, "delete", p)


    # -- the fold of cycles over a (k, tau) plane --

    def action_fold_curve(self) -> None:
        """Compute the shown sweep's fold curve in a worker (once per session), then draw
        it over the phase diagram."""
        shown = self._shown
        if self._fold_for is not None:  # one at a time: each takes a core for minutes
            done, total = self._fold_done
            self.notify(f"still computing the fold of cycles of sweep {self._fold_for} "
                        f"(tau {done}/{total})")
        elif shown is None:
            self.notify("no sweep to draw the fold of cycles over", severity="warning")
        elif not fold_overlay.has_fold_plane(shown.spec):
            across = ", ".join(fold_overlay.FOLD_PARAMS)
            self.notify(f"the fold of cycles is drawn over (x, tau) phase diagrams only, x one "
                        f"of {across}; this sweep is not one", severity="warning")
        elif shown.id in self.app.fold_curves:
            self.notify(f"the fold of cycles of sweep {shown.id} is drawn (• in the diagram)")
        else:
            assert shown.spec.y is not None  # a (k, tau) plane
            total = len(shown.spec.y.values())
            self._fold_for, self._fold_done = shown.id, (0, total)
            self.notify(f"computing the fold of cycles of sweep {shown.id}: one continuation "
                        f"per tau ({total}), seconds to minutes")
            self.compute_fold(shown.id, shown.spec, total)

    @work(thread=True, group="fold-curve")
    def compute_fold(self, sweep_id: int, spec: SweepSpec, total: int) -> None:
        worker = get_current_worker()
        done = 0

        def progress(tau: float, fold: float | None) -> None:
            nonlocal done
            done += 1
            self.post_message(self.FoldProgress(sweep_id, spec.x.param, done, total, tau, fold))
            if worker.is_cancelled:
                raise FoldCancelled

        try:
            curve = fold_overlay.fold_overlay(spec, progress)
        except FoldCancelled:
            return
        except Exception as exc:  # a failed continuation is shown, never a traceback
            self.post_message(self.FoldFailed(sweep_id, f"{type(exc).__name__}: {exc}"))
            return
        if curve is None:  # has_fold_plane was checked: not expected
            self.post_message(self.FoldFailed(sweep_id, "not a (k, tau) plane"))
            return
        self.post_message(self.FoldComputed(sweep_id, curve))

    @on(FoldProgress)
    def _fold_progress(self, message: FoldProgress) -> None:
        self._fold_done = (message.done, message.total)
        found = (f"{message.param} = {message.fold:.5g}" if message.fold is not None
                 else "no fold")
        # in the header: a notification per tau would pile up
        self.sub_title = (f"fold of cycles: tau {message.done}/{message.total} "
                          f"(τ = {message.tau:.4g}: {found})")

    @on(FoldComputed)
    def _fold_computed(self, message: FoldComputed) -> None:
        self._fold_for, self.sub_title = None, None
        self.app.fold_curves[message.sweep_id] = message.curve
        n = len(message.curve[0])
        self.notify(f"fold of cycles of sweep {message.sweep_id}: "
                    + (f"{n} points, drawn as •" if n else
                       "none in this plane (supercritical Hopf points)"))
        self.refresh_data()

    @on(FoldFailed)
    def _fold_failed(self, message: FoldFailed) -> None:
        self._fold_for, self.sub_title = None, None
        self.app.notify_text(f"could not compute the fold of cycles of sweep {message.sweep_id}: "
                             f"{message.cause}", severity="error", timeout=10)
