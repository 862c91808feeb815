"""Queue and workers: the live workers and what each runs, and what the runs they hold are
(claimed in a batch, or computing: ``sweeps.progress.claimed_text``, as `slopetui status`
says it); pause, resume, cancel (which asks first, in the modal of ``screens.confirm``:
one key once cancelled 1,072 runs)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from rich.text import Text
from textual import work
from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Vertical
from textual.message import Message
from textual.widgets import DataTable, Header, Static

from slopetui.display_text import terminal_safe
from slopetui.sweeps.control import EXPLAINED
from slopetui.sweeps.progress import (
    SweepProgress,
    WorkerInfo,
    claimed_line,
    live_workers,
    sweep_progress,
)
from slopetui.tui.messages import StoreFailed
from slopetui.tui.screens.base import SlopeScreen
from slopetui.tui.screens.confirm import ask_then_control
from slopetui.tui.widgets.steady_footer import SteadyFooter


class QueueScreen(SlopeScreen[None]):
    # short labels: the footer holds the app's few keys beside these at 80 columns
    BINDINGS = [
        Binding("p", "control('pause')", "Pause", id="queue.pause",
                tooltip=EXPLAINED["pause"]),
        Binding("r", "control('resume')", "Resume", id="queue.resume",
                tooltip=EXPLAINED["resume"]),
        Binding("c", "control('cancel')", "Cancel", id="queue.cancel",
                tooltip=EXPLAINED["cancel"]),
    ]

    def __init__(self) -> None:
        super().__init__()
        #: The sweeps as last loaded (the cancel question names the sweep and its runs).
        self._sweeps: list[SweepProgress] = []

    @dataclass
    class Loaded(Message):
        sweeps: list[SweepProgress]
        workers: list[WorkerInfo]
        claimed: str  # claimed_line: "" when no run is held

    def compose(self) -> ComposeResult:
        yield Header()
        yield Static("Workers", id="worker-title", classes="section-title")
        workers: DataTable[Any] = DataTable(id="worker-table", cursor_type="row")
        workers.add_columns("worker", "running", "jobs done", "heartbeat", "since")
        yield workers
        yield Static("", id="queue-claimed")
        yield Static("Sweeps (p pause, r resume, c cancel the highlighted one)",
                     classes="section-title")
        sweeps: DataTable[Any] = DataTable(id="queue-table", cursor_type="row", zebra_stripes=True)
        sweeps.add_columns("id", "status", "queued", "running", "done", "failed", "cancelled",
                           "name")
        with Vertical(id="queue-area"):  # the table as tall as its rows (slopetui.tcss)
            yield sweeps
        yield SteadyFooter()

    def on_mount(self) -> None:
        self.refresh_while_shown()
        self.query_one("#queue-table").focus()

    def refresh_data(self) -> None:
        if self.db is not None:
            self.load()

    @work(thread=True, exclusive=True, group="queue-load")
    def load(self) -> None:
        db = self.db
        if db is None:  # refresh_data starts this once the store is open
            return
        try:
            workers = live_workers(db)
            self.post_message(self.Loaded(sweep_progress(db), workers,
                                          claimed_line(db, len(workers))))
        except Exception as exc:
            self.post_message(StoreFailed("read the queue", f"{type(exc).__name__}: {exc}"))

    def on_queue_screen_loaded(self, message: Loaded) -> None:
        workers = self.query_one("#worker-table", DataTable)
        workers.clear()
        # stored text (worker ids, statuses, names) as escaped Text: a str cell is markup
        for w in message.workers:
            workers.add_row(Text(terminal_safe(w.id)),
                            f"run {w.run_id}" if w.run_id else "idle", str(w.jobs_done),
                            f"{w.heartbeat_age_s:.0f} s ago", f"{w.started_at:%H:%M:%S}")
        # the way to start them in the title: in a cell it pushed "since" off 80 columns
        self.query_one("#worker-title", Static).update(
            "Workers" if message.workers else
            "Workers: none live (slopetui worker --detach starts them)")
        if not message.workers:
            workers.add_row("no live workers", "", "", "", "")
        claimed = self.query_one("#queue-claimed", Static)
        claimed.update(message.claimed)
        claimed.display = bool(message.claimed)
        table = self.query_one("#queue-table", DataTable)
        row = table.cursor_row
        # The cursor stays on its sweep, not its row: p, r and c act on the highlighted
        # sweep, and a sweep submitted since is listed first (newest first), which would
        # move every other sweep down a row under a cursor kept by its row number.
        kept = (table.coordinate_to_cell_key(table.cursor_coordinate).row_key.value
                if table.row_count else None)
        table.clear()
        self._sweeps = message.sweeps
        for p in message.sweeps:
            c = p.counts
            table.add_row(str(p.id), Text(terminal_safe(p.status)), str(c.get("queued", 0)),
                          str(c.get("running", 0)), str(p.done), str(p.failed),
                          str(c.get("cancelled", 0)), Text(terminal_safe(p.name)),
                          key=str(p.id))
        if message.sweeps:
            ids = [str(p.id) for p in message.sweeps]
            at = ids.index(kept) if kept in ids else min(row, len(ids) - 1)
            table.move_cursor(row=at, animate=False)

    def action_control(self, action: str) -> None:
        table = self.query_one("#queue-table", DataTable)
        if table.row_count == 0 or self.db is None:
            return
        key = table.coordinate_to_cell_key(table.cursor_coordinate).row_key.value
        if key is None:
            return
        sweep = next((p for p in self._sweeps if p.id == int(key)), None)
        if sweep is not None:  # cancel asks first
            ask_then_control(self.app, action, sweep)
