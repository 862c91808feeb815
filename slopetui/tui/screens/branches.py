"""Branches: the stored continuations of periodic orbits (``slopetui continue --submit``),
in a second table the stored hysteresis sweeps (``slopetui hysteresis --submit``) and in a
third the curves in two parameters (``slopetui continue --param2 ... --submit``: a fold of
cycles or a Hopf curve, drawn in its plane with its codimension-two points); the
highlighted one's diagram, filling as a worker saves its points. The highlighted row of the
focused table is the one drawn (tab moves between the tables)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from rich.text import Text
from textual import events, on, work
from textual.app import ComposeResult
from textual.binding import Binding
from textual.message import Message
from textual.widgets import DataTable, Header, Static

from core.params import PARAM_NAMES, Params
from slopetui.display_text import terminal_safe
from slopetui.plots.branch_plot import render_branch
from slopetui.plots.canvas import axis_label
from slopetui.plots.curve_plot import render_curve
from slopetui.plots.hysteresis_plot import render_hysteresis
from slopetui.sweeps.branch_records import BifurcationRecord
from slopetui.sweeps.branches import ContinuationRow, StoredBranch, branch_of, listing, start_name
from slopetui.sweeps.curves import CURVE_NAMES, StoredCurve, curve_of
from slopetui.sweeps.curves import listing as curve_listing
from slopetui.sweeps.hysteresis_runs import (
    HysteresisRow,
    StoredHysteresis,
    WarmRecord,
    hysteresis_of,
)
from slopetui.sweeps.hysteresis_runs import listing as hysteresis_listing
from slopetui.tui.messages import StoreFailed
from slopetui.tui.screens.base import SlopeScreen
from slopetui.tui.widgets.plot_view import PlotView, Renderer
from slopetui.tui.widgets.steady_footer import SteadyFooter

#: The bifurcations column is cut to this many characters, so the table fits 80 columns.
FOUND_WIDTH = 24
EMPTY_HINT = ("No continuations yet: c queues one (from the Hopf point or an orbit), h a "
              "hysteresis sweep; the pool computes them point by point. Curves in two "
              "parameters, queued from the command line, show here too.")
#: What is highlighted: ("branch", continuation id), ("hysteresis", sweep id) or
#: ("curve", curve id).
Selection = tuple[str, int]
#: The table of each kind of row, in the screen's order.
TABLES = {"branch": "#branch-table", "hysteresis": "#hyst-table", "curve": "#curve-table"}
KIND_OF_TABLE = {table[1:]: kind for kind, table in TABLES.items()}
Chosen = StoredBranch | StoredHysteresis | StoredCurve


def start_text(row: ContinuationRow) -> str:
    """Where a branch starts: "hopf1 k=1.1926 τ=2" (the first Hopf point in the parameter,
    once found, and the fixed k and tau) or "orbit k=5 τ=2" (the parameters simulated)."""
    param, start = str(row.param), str(row.start)
    parts = [terminal_safe(start_name(row))]
    if start == "hopf" and row.hopf_value is not None:
        parts.append(f"{axis_label(param)}={row.hopf_value:.5g}")
    elif start != "hopf" and param not in ("k", "tau"):
        parts.append(f"{axis_label(param)}={getattr(row, param):.4g}")
    parts += [f"{axis_label(name)}={getattr(row, name):.4g}" for name in ("k", "tau")
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
    status = str(row.status)
    if branch.bifurcations:
        found = "bifurcations: " + ", ".join(
            f"{terminal_safe(str(b['type']))} {axis_label(param)} = {b['value']:.8g} "
            f"(period {b['period']:.5g})" for b in branch.bifurcations)
    elif status == "done":
        found = "no bifurcation on this branch"
    else:
        found = f"{terminal_safe(status)}: {len(branch.points)} points so far"
    if row.criticality:
        which = "" if row.hopf_branch is None else f" {row.hopf_branch}"  # the n-th
        found += f"; {terminal_safe(str(row.criticality))} Hopf point{which}"
    if row.error:
        last = str(row.error).strip().splitlines()[-1:] or [""]
        end = Text(f"error: {terminal_safe(last[0])}", style="bold red")
    elif row.end_reason:
        end = Text(f"end: {terminal_safe(str(row.end_reason))}")
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


def _kind_of(first: WarmRecord) -> str:
    """The kind of state a branch starts in, as core.hysteresis.past reads it."""
    growth = first["growth"]
    if first["regime"] == "sliding" and not first["jumped"] and not growth > 0.0:
        return "rest"
    return "the cycle" if first["regime"] == "oscillatory" else terminal_safe(str(first["regime"]))


def change_text(param: str, name: str, points: Sequence[WarmRecord], value: float | None,
                bracket: tuple[float | None, float | None] = (None, None)) -> str:
    """e.g. "up leaves rest at k = 6.143 [6.077, 6.269]" (refined, inside its grid bracket:
    the last value on the old attractor, the first on the new; a sweep stored before
    brackets were kept shows the grid's value alone) or "down keeps the cycle throughout"."""
    if not points:
        return f"{name}: no points"
    what = _kind_of(points[0])
    if value is None:
        return f"{name} keeps {what} throughout"
    before, after = bracket
    within = "" if before is None or after is None else f" [{before:.5g}, {after:.5g}]"
    return f"{name} leaves {what} at {axis_label(param)} = {value:.5g}{within}"


def hysteresis_detail(sweep: StoredHysteresis) -> Text:
    """The highlighted hysteresis sweep in two lines: where each branch changes regime
    once done (else its status and progress), then its error's last line, if any."""
    row, param = sweep.row, sweep.param
    status = str(row.status)
    if status == "done":
        found = (change_text(param, "up", sweep.up, row.onset_up,
                             (row.onset_up_before, row.onset_up_after)) + ", "
                 + change_text(param, "down", sweep.down, row.offset_down,
                               (row.offset_down_before, row.offset_down_after)))
    else:
        found = (f"{terminal_safe(status)}: {row.n_done} of {2 * row.n_points} points "
                 "so far")
    if row.error:
        last = str(row.error).strip().splitlines()[-1:] or [""]
        return Text.assemble(found, "\n", Text(f"error: {terminal_safe(last[0])}",
                                               style="bold red"))
    return Text.assemble(found, "\n", f"{row.n_done} points, {row.runtime_s:.1f} s")


def hysteresis_renderer(sweep: StoredHysteresis) -> Renderer:
    """Draws both branches at the PlotView's size (a pure function of the records)."""
    title = f"hysteresis {sweep.id} in {sweep.param}"
    up, down = sweep.up, sweep.down

    def draw(width: int, height: int, color: bool) -> str:
        return render_hysteresis(sweep.param, up, down, title=title, width=width,
                                 height=height, color=color)
    return draw


def range_text(row: HysteresisRow) -> str:
    """e.g. "8→12 τ=2": the values followed, and the delay."""
    return f"{row.start:.4g}→{row.stop:.4g} {axis_label('tau')}={row.tau:.4g}"


def _value(value: float | None) -> str:
    return "" if value is None else f"{value:.5g}"


def curve_found_text(name: str, second: str, found: Sequence[dict[str, Any]], *,
                     digits: int = 5) -> str:
    """The codimension-two points, e.g. "bautin k=26.225 τ=0.64995"."""
    return ", ".join(f"{terminal_safe(str(b['type']))} {axis_label(name)}={b[name]:.{digits}g} "
                     f"{axis_label(second)}={b[second]:.{digits}g}" for b in found)


def curve_detail(curve: StoredCurve) -> Text:
    """The highlighted curve in two lines: its codimension-two points once done (else its
    status and progress), then why it ended or its error's last line."""
    row = curve.row
    status = str(row.status)
    if curve.bifurcations:
        found = "found: " + curve_found_text(curve.param, curve.second, curve.bifurcations,
                                             digits=8)
    elif status == "done":
        found = "no codimension-two point on this curve"
    else:
        found = f"{terminal_safe(status)}: {row.n_points} points so far"
    if row.error:
        last = str(row.error).strip().splitlines()[-1:] or [""]
        return Text.assemble(found, "\n", Text(f"error: {terminal_safe(last[0])}",
                                               style="bold red"))
    end = f"end: {terminal_safe(str(row.end_reason))}; " if row.end_reason else ""
    return Text.assemble(found, "\n", f"{end}{row.n_points} points, {row.runtime_s:.1f} s")


def curve_renderer(curve: StoredCurve) -> Renderer:
    """Draws the curve in its plane at the PlotView's size (a pure function of records)."""
    kind = str(curve.row.kind)
    title = f"curve {curve.id}: {CURVE_NAMES.get(kind, kind)} in ({curve.param}, {curve.second})"
    points, found = list(curve.points), list(curve.bifurcations)

    def draw(width: int, height: int, color: bool) -> str:
        return render_curve(curve.param, curve.second, points, found, title=title,
                            width=width, height=height, color=color, kind=kind)
    return draw


class BranchesScreen(SlopeScreen[None]):
    """The highlighted continuation or hysteresis sweep is drawn below the lists; a running
    one grows as its points are saved (the periodic refresh)."""

    # The layout is this screen's alone; kept here with the screen (see slopetui.tcss for
    # the other screens'). At 80x24: header 1, tables 6 (4 + 4 when both kinds are
    # stored, 3 + 3 + 3 with curves too: each table's header and two rows, its cursor row
    # scrolled into view; a table with no rows is hidden unless all are empty), detail 2,
    # plot >= 11 (12 unless all three kinds are stored), footer 1.
    DEFAULT_CSS = """
    #branch-table, #hyst-table, #curve-table { height: auto; max-height: 6; }
    BranchesScreen.-both #branch-table, BranchesScreen.-both #hyst-table,
    BranchesScreen.-both #curve-table { max-height: 4; }
    BranchesScreen.-three #branch-table, BranchesScreen.-three #hyst-table,
    BranchesScreen.-three #curve-table { max-height: 3; }
    BranchesScreen.-three #branch-plot { min-height: 11; }
    #branch-detail { height: auto; max-height: 3; padding: 0 1; background: $boost; }
    #branch-plot { height: 1fr; }
    """

    @dataclass
    class Loaded(Message):
        branches: list[StoredBranch]
        sweeps: list[StoredHysteresis]
        curves: list[StoredCurve]
        #: The highlighted continuation with its points and bifurcations, hysteresis
        #: sweep with its points, or curve with its points and codimension-two points.
        chosen: Chosen | None
        #: Bifurcations of each finished continuation by id (the table's column).
        found: dict[int, list[BifurcationRecord]]
        #: Codimension-two points of each finished curve by id (the table's column).
        curve_found: dict[int, list[dict[str, Any]]]

    BINDINGS = [
        Binding("c", "app.open_analysis('continuation')", "New continuation",
                id="branches.continuation",
                tooltip="The form of a continuation of orbits (slopetui continue --submit)"),
        Binding("h", "app.open_analysis('hysteresis')", "New hysteresis",
                id="branches.hysteresis",
                tooltip="The form of a hysteresis sweep (slopetui hysteresis --submit)"),
    ]

    def __init__(self) -> None:
        super().__init__()
        self.selected: Selection | None = None
        #: Bifurcations of finished continuations by id: written once, with the status
        #: "done", so read once (listing() gives rows without them).
        self._found: dict[int, list[BifurcationRecord]] = {}
        #: Codimension-two points of finished curves by id, read once likewise.
        self._curve_found: dict[int, list[dict[str, Any]]] = {}
        #: The highlighted continuation, hysteresis sweep or curve, as last read.
        self._chosen: Chosen | None = None
        #: (kind, id, points, status) of what is drawn: redraw only when it changed.
        self._drawn: tuple[str, int, int, str] | None = None

    def compose(self) -> ComposeResult:
        yield Header()
        table: DataTable[Any] = DataTable(id="branch-table", cursor_type="row",
                                          zebra_stripes=True)
        table.add_columns("id", "param", "start", "status", "points", "criticality",
                          "bifurcations")
        yield table
        sweeps: DataTable[Any] = DataTable(id="hyst-table", cursor_type="row",
                                           zebra_stripes=True)
        sweeps.add_columns("hysteresis", "param", "range", "status", "points", "onset up",
                           "offset down")
        sweeps.display = False
        yield sweeps
        curves: DataTable[Any] = DataTable(id="curve-table", cursor_type="row",
                                           zebra_stripes=True)
        curves.add_columns("curve", "kind", "plane", "status", "points", "found")
        curves.display = False
        yield curves
        yield Static("Opening the store…", id="branch-detail")
        yield PlotView(id="branch-plot")
        yield SteadyFooter()

    def on_mount(self) -> None:
        self.refresh_while_shown()
        self.query_one("#branch-table").focus()

    def refresh_data(self) -> None:
        if self.db is not None:
            self.load(self.selected)
        else:  # being opened, or it could not be: say which, and how to retry
            self.query_one("#branch-detail", Static).update(self.app.store_status)

    @work(thread=True, exclusive=True, group="branches-load")
    def load(self, selected: Selection | None) -> None:
        db = self.db
        if db is None:  # refresh_data starts this once the store is open
            return
        try:
            branches = listing(db)
            sweeps = hysteresis_listing(db)
            curves = curve_listing(db)
            if selected is None:
                selected = _first(branches, sweeps, curves)
            chosen: Chosen | None = None
            if selected is not None:
                kind, ident = selected
                chosen = (branch_of(db, ident) if kind == "branch" else
                          hysteresis_of(db, ident) if kind == "hysteresis" else
                          curve_of(db, ident))
            for b in branches:
                if b.row.status == "done" and b.id not in self._found:
                    whole = (chosen if isinstance(chosen, StoredBranch) and chosen.id == b.id
                             else branch_of(db, b.id))
                    self._found[b.id] = whole.bifurcations if whole is not None else []
            for c in curves:
                if c.row.status == "done" and c.id not in self._curve_found:
                    read = (chosen if isinstance(chosen, StoredCurve) and chosen.id == c.id
                            else curve_of(db, c.id))
                    self._curve_found[c.id] = read.bifurcations if read is not None else []
        except Exception as exc:  # a locked or vanished database: say so, keep running
            self.post_message(StoreFailed("read the continuations",
                                          f"{type(exc).__name__}: {exc}"))
            return
        self.post_message(self.Loaded(branches, sweeps, curves, chosen, dict(self._found),
                                      dict(self._curve_found)))

    def on_branches_screen_loaded(self, message: Loaded) -> None:
        branches, sweeps, curves = message.branches, message.sweeps, message.curves
        branch_table = self.query_one("#branch-table", DataTable)
        hyst_table = self.query_one("#hyst-table", DataTable)
        curve_table = self.query_one("#curve-table", DataTable)
        branch_table.display = bool(branches) or not (sweeps or curves)
        hyst_table.display = bool(sweeps)
        curve_table.display = bool(curves)
        kinds = sum(bool(rows) for rows in (branches, sweeps, curves))
        self.set_class(kinds == 2, "-both")
        self.set_class(kinds == 3, "-three")
        if not branches and branch_table.has_focus and (sweeps or curves):
            (hyst_table if sweeps else curve_table).focus()  # the only rows there are
        if self.selected is None:
            self.selected = _first(branches, sweeps, curves)
        self._fill_table(branches, message.found)
        self._fill_sweeps(sweeps)
        self._fill_curves(curves, message.curve_found)
        if not branches and not sweeps and not curves:
            self.query_one("#branch-detail", Static).update(EMPTY_HINT)
        self._show(message.chosen)

    def _refill(self, kind: str, rows: list[tuple[int, tuple[Any, ...]]]) -> None:
        """Fill the table of ``kind`` with ``rows`` ((id, cells), the cells of stored text
        escaped Text: a str cell would be read as markup), its cursor kept on the selected
        row (its own kind), else where it was.

        Refilled without RowHighlighted: putting the cursor back on the selected row is no
        choice of the user's. clear() puts the cursor on row 0 and the first row added is
        announced as highlighted; _row_highlighted took it for a choice (the table has the
        focus) and loaded the first continuation, then the selected one again
        (move_cursor): with any row but the first selected, every load refilled the table
        and started two more, a whole core on an idle screen (as on the sweeps screen,
        SweepsScreen._fill_table)."""
        table = self.query_one(TABLES[kind], DataTable)
        keep = table.cursor_row
        with table.prevent(DataTable.RowHighlighted):
            table.clear()
            for ident, cells in rows:
                table.add_row(*cells, key=str(ident))
            if not rows:
                return
            ids = [ident for ident, _ in rows]
            selected = self.selected[1] if self.selected and self.selected[0] == kind else None
            row_index = ids.index(selected) if selected in ids else min(keep, len(ids) - 1)
            table.move_cursor(row=row_index, animate=False)

    def _fill_table(self, branches: list[StoredBranch],
                    found: dict[int, list[BifurcationRecord]]) -> None:
        self._refill("branch", [
            (b.id, (str(b.id), Text(axis_label(terminal_safe(b.param))),
                    Text(start_text(b.row)), Text(terminal_safe(str(b.row.status))),
                    str(b.row.n_points), Text(terminal_safe(str(b.row.criticality or ""))),
                    Text(cut(found_text(b.param, found.get(b.id, [])), FOUND_WIDTH))))
            for b in branches])

    def _fill_sweeps(self, sweeps: list[StoredHysteresis]) -> None:
        self._refill("hysteresis", [
            (h.id, (str(h.id), Text(axis_label(terminal_safe(h.param))),
                    Text(range_text(h.row)), Text(terminal_safe(str(h.row.status))),
                    f"{h.row.n_done}/{2 * h.row.n_points}", _value(h.row.onset_up),
                    _value(h.row.offset_down)))
            for h in sweeps])

    def _fill_curves(self, curves: list[StoredCurve],
                     found: dict[int, list[dict[str, Any]]]) -> None:
        self._refill("curve", [
            (c.id, (str(c.id), Text(terminal_safe(str(c.row.kind))),
                    Text(terminal_safe(f"({axis_label(c.param)}, {axis_label(c.second)})")),
                    Text(terminal_safe(str(c.row.status))), str(c.row.n_points),
                    Text(cut(curve_found_text(c.row.param, c.row.param2, found.get(c.id, [])),
                             FOUND_WIDTH))))
            for c in curves])

    def analysis_point(self) -> tuple[Params, str] | None:
        """Where an analysis opened from here starts (SlopeApp.analysis_point): the point
        the highlighted continuation or hysteresis sweep started from; None with none."""
        chosen = self._chosen
        if chosen is None:
            return None
        kind = ("continuation" if isinstance(chosen, StoredBranch) else
                "hysteresis sweep" if isinstance(chosen, StoredHysteresis) else "curve")
        try:
            at = Params(**{n: getattr(chosen.row, n) for n in PARAM_NAMES})
        except ValueError:  # a hand-edited row: the form opens at the defaults instead
            return None
        return at, f"{kind} {chosen.id}'s point"

    def _show(self, chosen: Chosen | None) -> None:
        self._chosen = chosen
        if chosen is None:
            self._drawn = None
            self.query_one(PlotView).show(None)
            return
        detail: Text
        renderer: Renderer
        if isinstance(chosen, StoredBranch):
            kind, detail, renderer = "branch", detail_text(chosen), branch_renderer(chosen)
        elif isinstance(chosen, StoredHysteresis):
            kind, detail = "hysteresis", hysteresis_detail(chosen)
            renderer = hysteresis_renderer(chosen)
        else:
            kind, detail, renderer = "curve", curve_detail(chosen), curve_renderer(chosen)
        self.query_one("#branch-detail", Static).update(detail)
        drawn = (kind, chosen.id, len(chosen.points), str(chosen.row.status))
        if drawn != self._drawn:  # a finished one is not redrawn every refresh
            self._drawn = drawn
            self.query_one(PlotView).show(renderer)

    def _select(self, table: DataTable[Any], key: str | None) -> None:
        kind = KIND_OF_TABLE[str(table.id)]
        if key is not None and (kind, int(key)) != self.selected:
            self.selected = (kind, int(key))
            self.refresh_data()

    @on(DataTable.RowHighlighted)
    def _row_highlighted(self, event: DataTable.RowHighlighted) -> None:
        # Only the focused table's cursor says what the user looks at (a refill announces
        # no highlight: _fill_table).
        if event.data_table.has_focus:
            self._select(event.data_table, event.row_key.value)

    def on_descendant_focus(self, event: events.DescendantFocus) -> None:
        """Tab into the other table: draw the row highlighted there."""
        table = event.widget
        if isinstance(table, DataTable) and table.row_count:
            key = table.coordinate_to_cell_key(table.cursor_coordinate).row_key.value
            self._select(table, key)


def _first(branches: list[StoredBranch], sweeps: list[StoredHysteresis],
           curves: list[StoredCurve]) -> Selection | None:
    """What is highlighted when nothing was: the newest of the first kind that has rows."""
    return (("branch", branches[0].id) if branches else
            ("hysteresis", sweeps[0].id) if sweeps else
            ("curve", curves[0].id) if curves else None)
