"""A sweep's name, tags and note, edited in a modal (``e`` on the sweeps screen, or the
palette): what ``slopetui rename``, ``tag`` and ``note`` change, checked as they are
(``slopetui.sweeps.annotations``) while typing, and saved in one background action.

``edit_labels(app, sweep_id)`` reads the sweep's labels off the UI thread, opens the modal
with them, and on save writes what changed and says so. Stored text is shown escaped
(an Input shows what it is given: a name another tool wrote with an escape sequence is
shown with it spelled out, and saving it as shown removes the sequence).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from rich.text import Text
from textual import on
from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Horizontal, Vertical
from textual.screen import ModalScreen
from textual.widgets import Button, Input, Label, Static, TextArea

from slopetui.display_text import terminal_safe, terminal_safe_lines
from slopetui.sweeps import annotations as sweep_annotations
from slopetui.sweeps.annotations import LabelError, SweepLabels

if TYPE_CHECKING:
    from slopetui.tui.app import SlopeApp


@dataclass(frozen=True)
class LabelsEdit:
    """What the modal gives back: the name, tags and note as typed, checked."""

    name: str
    tags: tuple[str, ...]
    note: str | None


def checked(name: str, tags: str, note: str) -> LabelsEdit:
    """The fields as stored, or the LabelError of the first that is not allowed."""
    return LabelsEdit(sweep_annotations.check_name(name),
                      tuple(sorted({sweep_annotations.check_tag(t, "tags") for t in tags.split()})),
                      sweep_annotations.check_note(note))


class SweepLabelsScreen(ModalScreen["LabelsEdit | None"]):
    """The sweep's name, tags and note in three fields; ctrl+s saves, escape keeps."""

    DEFAULT_CSS = """
    SweepLabelsScreen { align: center middle; }
    #labels-box {
        width: 72; max-width: 100%; height: auto; max-height: 100%; padding: 0 1;
        border: thick $accent; background: $surface;
    }
    #labels-box Label { margin-top: 1; }
    #labels-note { height: 5; }
    #labels-error { color: $error; height: auto; }
    #labels-buttons { height: auto; align-horizontal: right; }
    #labels-buttons Button { margin-left: 2; }
    """

    BINDINGS = [
        Binding("ctrl+s", "save", "Save", priority=True),
        Binding("escape", "keep", "Keep", show=False),
    ]

    def __init__(self, labels: SweepLabels) -> None:
        super().__init__()
        self.labels = labels

    def compose(self) -> ComposeResult:
        with Vertical(id="labels-box"):
            yield Static(Text(f"Sweep {self.labels.id}: name, tags and note"), id="labels-title")
            yield Label("name")
            yield Input(terminal_safe(self.labels.name), id="labels-name")
            yield Label("tags (separated by spaces)")
            yield Input(terminal_safe(" ".join(self.labels.tags)), placeholder="e.g. paper fig4",
                        id="labels-tags")
            yield Label("note")
            yield TextArea(terminal_safe_lines(self.labels.note or ""), id="labels-note",
                           tab_behavior="focus", soft_wrap=True)
            yield Static("", id="labels-error", markup=False)
            with Horizontal(id="labels-buttons"):
                yield Button("Keep (esc)", id="labels-keep")
                yield Button("Save (ctrl+s)", variant="primary", id="labels-save")

    def on_mount(self) -> None:
        self.query_one("#labels-name", Input).focus()
        #: The fields' text as the modal opened, by field: what unsaved compares with.
        self.opened = self._fields()

    def _fields(self) -> dict[str, str]:
        return {"name": self.query_one("#labels-name", Input).value,
                "tags": self.query_one("#labels-tags", Input).value,
                "note": self.query_one("#labels-note", TextArea).text}

    def unsaved(self) -> str | None:
        """What quitting now would lose, in a sentence, or None if every field is as it
        opened: the app asks before a quit (ctrl+q) that would throw typed text away
        (slopetui.tui.app)."""
        opened = getattr(self, "opened", None)
        if opened is None:  # not mounted yet: nothing typed
            return None
        changed = [field for field, text in self._fields().items() if opened[field] != text]
        if not changed:
            return None
        return (f"Sweep {self.labels.id}'s {', '.join(changed)} "
                f"{'is' if len(changed) == 1 else 'are'} not saved: what you typed would be "
                "lost.")

    def edit(self) -> LabelsEdit | None:
        """The fields checked; None (and the reason shown) if one is not allowed."""
        try:
            found = checked(self.query_one("#labels-name", Input).value,
                            self.query_one("#labels-tags", Input).value,
                            self.query_one("#labels-note", TextArea).text)
        except LabelError as exc:
            self.query_one("#labels-error", Static).update(Text(terminal_safe(exc)))
            self.query_one("#labels-save", Button).disabled = True
            return None
        self.query_one("#labels-error", Static).update("")
        self.query_one("#labels-save", Button).disabled = False
        return found

    @on(Input.Changed)
    @on(TextArea.Changed)
    def _check(self) -> None:
        self.edit()  # the error line follows the typing

    @on(Button.Pressed, "#labels-save")
    def action_save(self) -> None:
        found = self.edit()
        if found is not None:
            self.dismiss(found)

    @on(Button.Pressed, "#labels-keep")
    def action_keep(self) -> None:
        self.dismiss(None)


def save_labels(app: SlopeApp, before: SweepLabels, after: LabelsEdit) -> None:
    """Write what changed between ``before`` and ``after`` off the UI thread, then say
    what was saved and refresh the screen in view."""
    db, sweep = app.db, before.id
    if after == LabelsEdit(before.name, before.tags, before.note):
        app.notify(f"sweep {sweep}: nothing changed")
        return

    def save() -> SweepLabels:
        if db is None:
            raise RuntimeError("the database is not open yet")
        if after.name != before.name:
            sweep_annotations.rename(db, sweep, after.name)
        if after.note != before.note:
            sweep_annotations.set_note(db, sweep, after.note or "")
        if after.tags != before.tags:
            sweep_annotations.change_tags(db, sweep, set(after.tags) - set(before.tags),
                                    set(before.tags) - set(after.tags))
        return sweep_annotations.labels(db, sweep)

    def saved(now: SweepLabels) -> None:
        app.notify_text(f"sweep {sweep} saved: {now.name!r}, tags: "
                        f"{', '.join(now.tags) or 'none'}, {'a note' if now.note else 'no note'}")
        app.refresh_active_screen()

    app.background.start(save, group="sweep-labels", done=saved,
                         failed=lambda exc: app.notify_text(
                             f"could not save sweep {sweep}: {exc}", severity="error",
                             timeout=8))


def edit_labels(app: SlopeApp, sweep_id: int) -> None:
    """Read the sweep's labels, open the modal on them, save what it gives back."""
    db = app.db

    def read() -> SweepLabels:
        if db is None:
            raise RuntimeError("the database is not open yet")
        return sweep_annotations.labels(db, sweep_id)

    def opened(labels: SweepLabels) -> None:
        app.push_screen(SweepLabelsScreen(labels),
                        lambda after: None if after is None else save_labels(app, labels, after))

    app.background.start(read, group="sweep-labels", done=opened,
                         failed=lambda exc: app.notify_text(
                             f"sweep {sweep_id}: {exc}", severity="error", timeout=8))
