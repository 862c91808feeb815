"""Branches: the stored continuations of periodic orbits (``slopetui continue --submit``),
and the highlighted one's bifurcation diagram, filling as a worker saves its points."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from rich.text import Text
from textual import on, work
from textual.app import ComposeResult
from textual.message import Message
from textual.widgets import DataTable, Footer, Header, Static

from slopetui.display_text import terminal_safe
from slopetui.plots.branch_plot import render_branch
from slopetui.plots.canvas import axis_label
from slopetui.sweeps.branch_records import BifurcationRecord
from slopetui.sweeps.branches import StoredBranch, branch_of, listing
from slopetui.tui.messages import StoreFailed
from slopetui.tui.screens.base import SlopeScreen
from slopetui.tui.widgets.plot_view import PlotView, Renderer

#: The bifurcations column is cut to this many characters, so the table fits 80 columns.
FOUND_WIDTH = 24
EMPTY_HINT = ("No continuations yet: queue one with slopetui continue --param k --from-hopf "
              "--submit; the workers compute it point by point.")


def start_text(row: Mapping[str, Any]) -> str:
    """Where a branch starts: "hopf k=1.1926 τ=2" (the Hopf point in the parameter, once
    found, and the fixed k and tau) or "orbit k=5 τ=2" (the parameters simulated)."""
    param, start = str(row["param"]), str(row["start"])
    parts = [terminal_safe(start)]
    if start == "hopf" and row["hopf_value"] is not None:
        parts.append(f"{axis_label(param)}={row['hopf_value']:.5g}")
    elif start != "hopf" and param not in ("k", "tau"):
        parts.append(f"{axis_label(param)}={row[param]:.4g}")
    parts += [f"{axis_label(name)}={row[name]:.4g}" for name in ("k", "tau")
              if not (start == "hopf" and name == param)]  # at the Hopf point it is found
    return " ".join(parts)


def found_text(param: str, found: Sequence[BifurcationRecord], *, digits: int = 5) -> str:
    """The bifurcations, e.g. "fold k=1.2139, torus k=3.05"."""
    return ", ".join(f"{terminal_safe(str(b['type']))} {axis_label(param)}="
                     f"{b['value']:.{digits}g}" for b in found)


def cut(text: str, width: int) -> str:
    return text if len(text) <= width else text[:width - 1] + "…"


def detail_text(branch: StoredBranch) -> Text:
    """The highlighted branch in two lines: what was found on it, then why it ended (or
    its error, whose last line says what went wrong)."""
    row, param = branch.row, branch.param
    status = str(row["status"])
    if branch.bifurcations:
        found = "bifurcations: " + ", ".join(
            f"{terminal_safe(str(b['type']))} {axis_label(param)} = {b['value']:.8g} "
            f"(period {b['period']:.5g})" for b in branch.bifurcations)
    elif status == "done":
        found = "no bifurcation on this branch"
    else:
        found = f"{terminal_safe(status)}: {len(branch.points)} points so far"
    if row["criticality"]:
        found += f"; {terminal_safe(str(row['criticality']))} Hopf point"
    if row["error"]:
        last = str(row["error"]).strip().splitlines()[-1:] or [""]
        end = Text(f"error: {terminal_safe(last[0])}", style="bold red")
    elif row["end_reason"]:
        end = Text(f"end: {terminal_safe(str(row['end_reason']))}")
    else:
        end = Text("")
    return Text.assemble(found, "\n", end)


def branch_renderer(branch: StoredBranch) -> Renderer:
    """Draws the branch at the PlotView's size (a pure function of its records)."""
    title = f"continuation {branch.id} in {branch.param}"
    points, bifurcations = list(branch.points), list(branch.bifurcations)

    def draw(width: int, height: int, color: bool) -> str:
        return render_branch(branch.param, points, bifurcations, title=title, width=width,
                             height=height, color=color)
    return draw


class BranchesScreen(SlopeScreen[None]):
    """The highlighted continuation is drawn below the list; a running one grows as its
    points are saved (the periodic refresh)."""

    # The layout is this screen's alone; kept here with the screen (see slopetui.tcss for
    # the other screens'). At 80x24: header 1, table 6, detail 2, plot >= 12, footer 1.
    DEFAULT_CSS = """
    #branch-table { height: 6; }
    #branch-detail { height: auto; max-height: 3; padding: 0 1; background: $boost; }
    #branch-plot { height: 1fr; }
    """

    @dataclass
    class Loaded(Message):
        branches: list[StoredBranch]
        #: The highlighted continuation with its points and bifurcations.
        chosen: StoredBranch | None
        #: Bifurcations of each finished continuation by id (the table's column).
        found: dict[int, list[BifurcationRecord]]

    def __init__(self) -> None:
        super().__init__()
        self.selected: int | None = None
        #: Bifurcations of finished continuations by id: written once, with the status
        #: "done", so read once (listing() gives rows without them).
        self._found: dict[int, list[BifurcationRecord]] = {}
        #: (id, points, status) of the branch drawn: redraw only when it changed.
        self._drawn: tuple[int, int, str] | None = None

    def compose(self) -> ComposeResult:
        yield Header()
        table: DataTable[Any] = DataTable(id="branch-table", cursor_type="row",
                                          zebra_stripes=True)
        table.add_columns("id", "param", "start", "status", "points", "criticality",
                          "bifurcations")
        yield table
        yield Static("Opening the store…", id="branch-detail")
        yield PlotView(id="branch-plot")
        yield Footer()

    def on_mount(self) -> None:
        self.set_interval(self.app.refresh_s, self.refresh_data)
        self.refresh_data()
        self.query_one("#branch-table").focus()

    def refresh_data(self) -> None:
        if self.db is not None:
            self.load(self.selected)

    @work(thread=True, exclusive=True, group="branches-load")
    def load(self, cid: int | None) -> None:
        db = self.db
        if db is None:  # refresh_data starts this once the store is open
            return
        try:
            branches = listing(db)
            if cid is None and branches:
                cid = branches[0].id
            chosen = branch_of(db, cid) if cid is not None else None
            for b in branches:
                if b.row["status"] == "done" and b.id not in self._found:
                    whole = chosen if chosen is not None and chosen.id == b.id else branch_of(db, b.id)
                    self._found[b.id] = whole.bifurcations if whole is not None else []
        except Exception as exc:  # a locked or vanished database: say so, keep running
            self.post_message(StoreFailed("read the continuations",
                                          f"{type(exc).__name__}: {exc}"))
            return
        self.post_message(self.Loaded(branches, chosen, dict(self._found)))

    def on_branches_screen_loaded(self, message: Loaded) -> None:
        self._fill_table(message.branches, message.found)
        self._show(message.chosen)

    def _fill_table(self, branches: list[StoredBranch],
                    found: dict[int, list[BifurcationRecord]]) -> None:
        table = self.query_one("#branch-table", DataTable)
        keep = table.cursor_row
        table.clear()
        for b in branches:
            row = b.row
            # stored text as escaped Text: a str cell would be read as markup
            table.add_row(str(b.id), Text(axis_label(terminal_safe(b.param))),
                          Text(start_text(row)), Text(terminal_safe(str(row["status"]))),
                          str(row["n_points"]),
                          Text(terminal_safe(str(row["criticality"] or ""))),
                          Text(cut(found_text(b.param, found.get(b.id, [])), FOUND_WIDTH)),
                          key=str(b.id))
        if not branches:
            self.query_one("#branch-detail", Static).update(EMPTY_HINT)
            return
        if self.selected is None:
            self.selected = branches[0].id
        ids = [b.id for b in branches]
        row_index = ids.index(self.selected) if self.selected in ids else min(keep, len(ids) - 1)
        table.move_cursor(row=row_index, animate=False)

    def _show(self, branch: StoredBranch | None) -> None:
        if branch is None:
            self._drawn = None
            self.query_one(PlotView).show(None)
            return
        self.query_one("#branch-detail", Static).update(detail_text(branch))
        drawn = (branch.id, len(branch.points), str(branch.row["status"]))
        if drawn != self._drawn:  # a finished branch is not redrawn every refresh
            self._drawn = drawn
            self.query_one(PlotView).show(branch_renderer(branch))

    @on(DataTable.RowHighlighted, "#branch-table")
    def _row_highlighted(self, event: DataTable.RowHighlighted) -> None:
        if event.row_key.value is not None:
            chosen = int(event.row_key.value)
            if chosen != self.selected:
                self.selected = chosen
                self.refresh_data()
