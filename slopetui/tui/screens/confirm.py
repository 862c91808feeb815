"""A small modal that asks before an action that cannot be taken back in one key (cancel
a sweep's queued runs, delete a sweep): one key once cancelled 1,072 runs at once.

``ask_then_control(app, action, sweep)`` (or ``ask_then_control_id`` with an id only) is
how a face of the application cancels or deletes a sweep: the question, then
``app.control_sweep`` on yes (pause and resume need no question: each undoes the other,
and resume undoes a cancel).

It is dismissed with True only by a deliberate choice (y, or the button that names the
action); n, escape and the other button keep things as they are. The safe button has the
focus, so that a stray enter keeps. The question is shown as plain text: it names a
sweep, whose stored name could otherwise be read as markup.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from rich.text import Text
from textual import on
from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Horizontal, Vertical
from textual.screen import ModalScreen
from textual.widgets import Button, Static

from slopetui.display_text import terminal_safe
from slopetui.sweeps.progress import SweepProgress, sweep_progress

if TYPE_CHECKING:
    from slopetui.tui.app import SlopeApp


class ConfirmScreen(ModalScreen[bool]):
    """``ConfirmScreen(question, yes="Cancel the sweep")``: True when confirmed."""

    DEFAULT_CSS = """
    ConfirmScreen { align: center middle; }
    #confirm-box {
        width: 64; max-width: 95%; height: auto; padding: 1 2;
        border: thick $warning; background: $surface;
    }
    #confirm-question { margin-bottom: 1; }
    #confirm-buttons { height: auto; align-horizontal: right; }
    #confirm-buttons Button { margin-left: 2; }
    """

    BINDINGS = [
        Binding("y", "answer(True)", "Yes", show=False),
        Binding("n", "answer(False)", "No", show=False),
        Binding("escape", "answer(False)", "Keep", show=False),
    ]

    def __init__(self, question: str, yes: str, no: str = "Keep") -> None:
        super().__init__()
        self.question, self.yes, self.no = question, yes, no

    def compose(self) -> ComposeResult:
        with Vertical(id="confirm-box"):
            yield Static(Text(self.question), id="confirm-question")
            with Horizontal(id="confirm-buttons"):
                yield Button(f"{self.yes} (y)", variant="error", id="confirm-yes")
                yield Button(f"{self.no} (n)", variant="primary", id="confirm-no")

    def on_mount(self) -> None:
        self.query_one("#confirm-no", Button).focus()

    def action_answer(self, yes: bool) -> None:
        self.dismiss(yes)

    @on(Button.Pressed)
    def _pressed(self, event: Button.Pressed) -> None:
        event.stop()
        self.dismiss(event.button.id == "confirm-yes")


def _runs(n: int) -> str:
    return f"{n:,} {'run' if n == 1 else 'runs'}"


def cancel_question(p: SweepProgress) -> str:
    """What c asks: the sweep, its queued runs that would be cancelled, and the way back."""
    queued = p.counts.get("queued", 0)
    running = f"; its {_runs(p.running)} running finish" if p.running else ""
    return (f"Cancel sweep {p.id} '{terminal_safe(p.name)}'?\n\n"
            f"Its {queued:,} queued {'run' if queued == 1 else 'runs'} would be "
            f"cancelled{running}. Resume (r) queues them again.")


def delete_question(p: SweepProgress) -> str:
    """What x asks: the sweep and how many runs go with it; nothing undoes a delete."""
    return (f"Delete sweep {p.id} '{terminal_safe(p.name)}' and its "
            f"{_runs(sum(p.counts.values()))}?\n\n"
            "Nothing undoes this. Runs of other sweeps that copied a result from its runs "
            "keep it.")


#: The actions that ask first: the question for a sweep, and the button that confirms.
QUESTIONS = {"cancel": (cancel_question, "Cancel the sweep"),
             "delete": (delete_question, "Delete the sweep")}


def ask_then_control(app: SlopeApp, action: str, sweep: SweepProgress) -> None:
    """Ask about ``action`` (one of QUESTIONS) on ``sweep`` in the modal, then on yes hand
    it to ``app.control_sweep``; other actions go to it at once."""
    if action not in QUESTIONS:
        app.control_sweep(action, sweep.id)
        return
    ask, yes = QUESTIONS[action]

    def answered(confirmed: bool | None) -> None:
        if confirmed:
            app.control_sweep(action, sweep.id)

    app.push_screen(ConfirmScreen(ask(sweep), yes), answered)


def ask_then_control_id(app: SlopeApp, action: str, sweep_id: int) -> None:
    """ask_then_control for a sweep known by its id only (the command palette's "cancel
    sweep 3"): its progress (what the question counts) is read in a background action
    (slopetui.tui.background), then the question is asked on the UI thread; an unknown
    sweep is said, not asked about, and so is a failed read."""
    if action not in QUESTIONS:
        app.control_sweep(action, sweep_id)
        return

    db = app.db

    def read() -> list[SweepProgress]:
        return sweep_progress(db, [sweep_id]) if db is not None else []

    def asked(found: list[SweepProgress]) -> None:
        if found:
            ask_then_control(app, action, found[0])
        else:
            app.notify(f"{action} sweep {sweep_id}: no such sweep", severity="error")

    app.background.start(
        read, done=asked, group="confirm-read",
        failed=lambda exc: app.notify_text(f"{action} sweep {sweep_id}: {type(exc).__name__}: "
                                           f"{exc}", severity="error", timeout=8))
