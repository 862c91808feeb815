"""Two sweeps' specs side by side in a modal (the palette: "compare sweeps 3 5"), as
``slopetui compare 3 5`` prints them (slopetui.sweeps.spec_compare): every setting, the
ones that differ marked and first-coloured; d shows only those.

``compare_sweeps(app, a, b)`` reads both specs off the UI thread, then opens the modal.
Names, keys and values are stored text: escaped, and never read as markup.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from rich.text import Text
from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Vertical
from textual.screen import ModalScreen
from textual.widgets import DataTable, Static

from slopetui.display_text import terminal_safe
from slopetui.sweeps.spec_compare import SpecComparison, compare_specs

if TYPE_CHECKING:
    from slopetui.tui.app import SlopeApp


class SpecCompareScreen(ModalScreen[None]):
    """The settings of two specs in three columns; d: only those that differ; esc closes."""

    DEFAULT_CSS = """
    SpecCompareScreen { align: center middle; }
    #spec-box { width: 96; max-width: 100%; height: 90%; border: thick $accent;
                background: $surface; padding: 0 1; }
    #spec-title { height: auto; }
    #spec-table { height: 1fr; }
    """

    BINDINGS = [
        Binding("d", "differences", "Only differences"),
        Binding("escape", "close", "Close"),
    ]

    def __init__(self, comparison: SpecComparison) -> None:
        super().__init__()
        self.comparison = comparison
        self.only_differences = False

    def compose(self) -> ComposeResult:
        c = self.comparison
        n = len(c.differences)
        with Vertical(id="spec-box"):
            yield Static(Text(f"sweep {c.a.id} {terminal_safe(c.a.name)!r} against sweep "
                              f"{c.b.id} {terminal_safe(c.b.name)!r}: {n} of "
                              f"{len(c.settings)} settings differ (*; d: only those; esc closes)"),
                         id="spec-title")
            yield DataTable(id="spec-table", cursor_type="row", zebra_stripes=True)

    def on_mount(self) -> None:
        self.fill()
        self.query_one("#spec-table").focus()

    def fill(self) -> None:
        table = self.query_one("#spec-table", DataTable)
        table.clear(columns=True)
        c = self.comparison
        table.add_columns("", "setting", f"sweep {c.a.id}", f"sweep {c.b.id}")
        shown = c.differences if self.only_differences else c.settings
        for s in shown:
            style = "bold" if s.differs else ""
            table.add_row("*" if s.differs else "", Text(terminal_safe(s.key), style=style),
                          Text(terminal_safe(s.a), style=style),
                          Text(terminal_safe(s.b), style=style))

    def action_differences(self) -> None:
        self.only_differences = not self.only_differences
        self.fill()

    def action_close(self) -> None:
        self.dismiss(None)


def compare_sweeps(app: SlopeApp, a: int, b: int) -> None:
    """Read the two specs, then show them side by side; an unknown sweep is said."""
    db = app.db

    def read() -> SpecComparison:
        if db is None:
            raise RuntimeError("the database is not open yet")
        return compare_specs(db, a, b)

    def show(found: SpecComparison) -> None:
        app.push_screen(SpecCompareScreen(found))

    app.background.start(read, group="spec-compare", done=show,
                         failed=lambda exc: app.notify_text(f"compare sweeps {a} and {b}: {exc}",
                                                            severity="error", timeout=8))
