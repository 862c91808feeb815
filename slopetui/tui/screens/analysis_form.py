"""A form that starts one analysis (a continuation, a hysteresis sweep, an orbit, a
certified re-run), the way the new-sweep form starts a sweep: every change is checked by
the same function the CLI calls (slopetui.sweeps.*_request, orbit_point,
certified_rerun), a refusal names the field (its input is marked) and its range, an
estimate is shown where one can be honestly computed, and ctrl+s starts it as a
background action (slopetui.tui.background): queued for the pool, or, for an orbit,
computed here and shown in the form.

What each analysis asks, checks and does is an ``Analysis`` (slopetui.tui.screens.analyses);
this screen only lays its fields out, in rows of label and input as the new-sweep form's
(slopetui.tcss's #form rules), and shows what the check says. Esc or ctrl+q on a form
that differs from what it opened with asks before throwing it away.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from rich.text import Text
from textual import on
from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Horizontal, VerticalScroll
from textual.widgets import Button, Header, Input, Label, Select, Static

from slopetui.tui.screens.base import SlopeScreen
from slopetui.tui.screens.confirm import ConfirmScreen
from slopetui.tui.widgets.steady_footer import SteadyFooter

if TYPE_CHECKING:
    from slopetui.store.database import Database


@dataclass(frozen=True)
class Field:
    """One input: ``name`` is what a refusal names (ParameterError.field, SpecError.field:
    the CLI's flag without its dashes), ``value`` what it opens with, ``choices`` a
    Select's values."""

    name: str
    label: str
    value: str
    choices: tuple[str, ...] = ()
    placeholder: str = ""


@dataclass(frozen=True)
class Checked:
    """A request the check accepted, and what starting it will take."""

    request: Any
    estimate: str


@dataclass(frozen=True)
class Analysis:
    """What a form asks, checks and starts.

    ``check`` takes the fields' text by name and returns the request with its estimate,
    or raises an error with a ``field`` (ParameterError, SpecError); it runs on every
    change, so it reads nothing slow. ``start`` runs in a thread with the store and the
    request and returns the line to show: queued forms close on it (``closes``), the
    orbit's stays open and shows it."""

    title: str
    rows: tuple[tuple[Field, ...], ...]
    check: Callable[[dict[str, str]], Checked]
    start: Callable[[Database, Any], str]
    verb: str = "Queue"
    closes: bool = True
    note: str = ""


def _input_id(name: str) -> str:
    return f"f-{name}"


class AnalysisFormScreen(SlopeScreen[None]):
    """One analysis's form (module docstring)."""

    AUTO_FOCUS = "#form Input, #form Select"
    DEFAULT_CSS = """
    AnalysisFormScreen #analysis-note { color: $text-muted; }
    AnalysisFormScreen #result { padding: 0 0 0 1; }
    """

    BINDINGS = [
        Binding("ctrl+s", "submit", "Start", id="analysis.submit", priority=True),
        Binding("tab", "app.focus_next", "Next field", id="analysis.next_field",
                tooltip="The next field (shift+tab: the one before)"),
        Binding("escape", "cancel", "Cancel", id="analysis.cancel"),
    ]

    def __init__(self, analysis: Analysis) -> None:
        super().__init__()
        self.analysis = analysis
        self.checked: Checked | None = None
        #: Every field's value as the form opened: what closing it would lose differs.
        self.opened: dict[str, str] = {}
        self.busy = False

    def compose(self) -> ComposeResult:
        yield Header()
        with VerticalScroll(id="form"):
            yield Static(self.analysis.title, id="analysis-title")
            for row in self.analysis.rows:
                cells: list[Any] = []
                for field in row:
                    cells.append(Label(field.label, classes="param-label"))
                    if field.choices:
                        cells.append(Select([(c, c) for c in field.choices], value=field.value,
                                            allow_blank=False, compact=True,
                                            id=_input_id(field.name), classes="spacing"))
                    else:
                        cells.append(Input(field.value, placeholder=field.placeholder,
                                           compact=True, id=_input_id(field.name),
                                           classes="num"))
                yield Horizontal(*cells, classes="form-row")
            yield Static("", id="estimate")
            yield Static("", id="form-error")
            yield Static("", id="result")
            with Horizontal(id="form-buttons"):
                yield Button(f"{self.analysis.verb} (ctrl+s)", variant="primary", id="submit")
                yield Button("Cancel (esc)", id="cancel")
            if self.analysis.note:
                yield Static(self.analysis.note, id="analysis-note")
        yield SteadyFooter()

    def on_mount(self) -> None:
        self.title = self.analysis.title
        self.sub_title = ""  # the app's would be cut at 80 columns after the title
        self.opened = self.values()
        self.validate_form()

    def values(self) -> dict[str, str]:
        """Every field's text, by its name."""
        out: dict[str, str] = {}
        for row in self.analysis.rows:
            for field in row:
                widget = self.query_one(f"#{_input_id(field.name)}")
                value = widget.value if isinstance(widget, (Input, Select)) else ""
                out[field.name] = str(value)
        return out

    def validate_form(self) -> Checked | None:
        for widget in self.query(".-invalid"):
            widget.remove_class("-invalid")
        error = self.query_one("#form-error", Static)
        try:
            checked = self.analysis.check(self.values())
        except ValueError as exc:  # ParameterError, SpecError: both name the field
            self.checked = None
            error.update(Text(f"✗ {exc}"))  # Text: a bracket in the input is not markup
            name = getattr(exc, "field", "")
            for widget in self.query(f"#{_input_id(name)}") if name else ():
                widget.add_class("-invalid")
            self.query_one("#estimate", Static).update("")
            return None
        self.checked = checked
        error.update("")
        self.query_one("#estimate", Static).update(Text(f"≈ {checked.estimate}"))
        return checked

    @on(Input.Changed)
    @on(Select.Changed)
    def _changed(self) -> None:
        self.validate_form()

    def unsaved(self) -> str | None:
        """What closing the form now would lose, or None if it is as it opened (the app
        asks before a ctrl+q that would throw a filled form away)."""
        changed = [name for name, value in self.values().items() if self.opened.get(name) != value]
        if not changed:
            return None
        return (f"The {self.analysis.title.lower()} form is not started: what you entered "
                f"({', '.join(changed[:4])}{' and more' if len(changed) > 4 else ''}) would "
                "be lost.")

    @on(Button.Pressed, "#submit")
    def action_submit(self) -> None:
        checked = self.validate_form()
        if checked is None:
            self.notify("fix the field marked in red first", severity="error")
            return
        db = self.db
        if db is None:
            self.notify("the database is not open yet", severity="error")
            return
        if self.busy:
            return
        self.busy = True
        self.query_one("#submit", Button).disabled = True
        start, request = self.analysis.start, checked.request
        if not self.analysis.closes:
            self.query_one("#result", Static).update("computing… (compiling kernels once "
                                                     "after an install takes ~15 s)")
        self.app.background.start(lambda: start(db, request), group="analysis",
                                  done=self._started, failed=self._failed)

    def _started(self, text: str) -> None:
        if self not in self.app.screen_stack:  # closed meanwhile: say it where it shows
            self.app.notify_text(text, timeout=15)
            return
        self.busy = False
        self.query_one("#submit", Button).disabled = False
        if self.analysis.closes:
            self.app.notify_text(text)
            if self.is_current:
                self.dismiss(None)
        else:
            self.query_one("#result", Static).update(Text(text))
            self.opened = self.values()  # what it computed is shown: nothing to lose

    def _failed(self, exc: Exception) -> None:
        cause = f"{type(exc).__name__}: {exc}"
        if self not in self.app.screen_stack:
            self.app.notify_text(f"{self.analysis.title}: {cause}", severity="error", timeout=15)
            return
        self.busy = False
        self.query_one("#submit", Button).disabled = False
        if self.analysis.closes:
            self.query_one("#form-error", Static).update(Text(f"✗ could not start: {cause}"))
        else:
            self.query_one("#result", Static).update(Text(f"✗ {cause}"))

    @on(Button.Pressed, "#cancel")
    def action_cancel(self) -> None:
        lost = self.unsaved()
        if lost is None:
            self.dismiss(None)
            return
        self.app.push_screen(ConfirmScreen(f"Close the form? {lost}", yes="Discard",
                                           no="Keep editing"),
                             self._close_if)

    def _close_if(self, discard: bool | None) -> None:
        if discard:
            self.dismiss(None)
