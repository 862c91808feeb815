"""Modals that show an error with its cause (never a traceback).

``ErrorScreen`` only says what went wrong. ``StoreErrorScreen`` is shown when the store
cannot be opened: without a store the application can do nothing, so it offers the ways
on — retry (a folder created meanwhile, a server started), open another store (a URL or
a file path, checked before it is tried), or quit. Closing it leaves the application
without a store; the sweeps screen then says so and how to come back here (ctrl+o).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Literal, TypeVar

from rich.text import Text
from textual import on
from textual.app import ComposeResult
from textual.binding import Binding
from textual.containers import Horizontal, Vertical
from textual.screen import ModalScreen
from textual.widgets import Button, Input, Static

from slopetui.store.database import parse_url, sqlite_path
from slopetui.store.failures import StoreError
from slopetui.store.location import sqlite_url

ResultT = TypeVar("ResultT")


class ErrorScreen(ModalScreen[ResultT]):
    """The error's title and cause, and a Close button (``ErrorScreen[None](title, cause)``;
    generic for the dialogs built on it that return a choice)."""

    BINDINGS = [Binding("escape", "dismiss", "Close"), Binding("q", "app.quit", "Quit")]

    def __init__(self, title: str, cause: str) -> None:
        super().__init__()
        self.title_text, self.cause = title, cause

    def compose(self) -> ComposeResult:
        with Vertical(id="error-box"):
            yield Static(self.title_text, id="error-title")
            yield Static(Text(self.cause), id="error-cause")  # Text: brackets are not markup
            yield Button("Close", variant="error", id="error-close")

    @on(Button.Pressed, "#error-close")
    def _close(self) -> None:
        self.dismiss()


def store_url(text: str) -> str:
    """The database URL for what was typed: a SQLAlchemy URL, or the path of a SQLite
    file (created if it does not exist, in a folder that must). ValueError says what is
    wrong, before anything is opened."""
    text = text.strip()
    if not text:
        raise ValueError("type a database URL (sqlite:///path/runs.db, "
                         "postgresql+psycopg://host/db) or the path of a file")
    if "://" in text:
        try:
            path = sqlite_path(parse_url(text))
        except StoreError as exc:
            raise ValueError(str(exc).removeprefix("--db: ")) from None
        url = text
    else:
        path = Path(text).expanduser().resolve()
        url = sqlite_url(path)  # escaped: a "#" or "?" in a file name is not URL syntax
    if path is not None:  # a folder named by mistake is refused here, not by SQLite later
        if path.is_dir():
            raise ValueError(f"{path} is a folder: name a database file in it")
        if not path.parent.is_dir():
            raise ValueError(f"there is no folder {path.parent}")
    return url


@dataclass(frozen=True)
class StoreChoice:
    """What to do after the store could not be opened: retry the same store, or open
    ``url`` instead."""

    action: Literal["retry", "open"]
    url: str | None = None


class StoreErrorScreen(ErrorScreen["StoreChoice | None"]):
    """Dismissed with the choice, or None when closed (the app stays without a store)."""

    AUTO_FOCUS = "#store-retry"
    BINDINGS = [
        Binding("r", "retry", "Retry", id="store_error.retry"),
        Binding("o", "choose", "Another store", id="store_error.other"),
        Binding("q", "app.quit", "Quit", id="store_error.quit"),
        Binding("escape", "close", "Close", id="store_error.close"),
    ]

    def __init__(self, cause: str) -> None:
        super().__init__("The store cannot be opened", cause)

    def compose(self) -> ComposeResult:
        with Vertical(id="error-box"):
            yield Static(self.title_text, id="error-title")
            yield Static(Text(self.cause), id="error-cause")  # Text: brackets are not markup
            with Vertical(id="store-other"):
                yield Input(placeholder="sqlite:///path/runs.db, a file path, or "
                                        "postgresql+psycopg://…", id="store-url")
                yield Static("", id="store-url-error")
            with Horizontal(id="store-buttons"):
                yield Button("Retry (r)", variant="primary", id="store-retry")
                yield Button("Another store (o)", id="store-choose")
                yield Button("Quit (q)", variant="error", id="store-quit")
                yield Button("Close (esc)", id="store-close")


    @on(Button.Pressed, "#store-retry")
    def action_retry(self) -> None:
        self.dismiss(StoreChoice("retry"))

    @on(Button.Pressed, "#store-choose")
    def action_choose(self) -> None:
        """Show the field for another store's URL or path (enter opens it)."""
        self.query_one("#store-other").display = True
        self.query_one("#store-url", Input).focus()

    @on(Button.Pressed, "#store-quit")
    def _quit(self) -> None:
        self.app.exit()

    @on(Button.Pressed, "#store-close")
    def action_close(self) -> None:
        """Close without a store; ctrl+o brings this back."""
        self.dismiss(None)

    @on(Input.Submitted, "#store-url")
    def _open_other(self, event: Input.Submitted) -> None:
        try:
            url = store_url(event.value)
        except ValueError as exc:
            self.query_one("#store-url-error", Static).update(Text(f"✗ {exc}"))
            return
        self.dismiss(StoreChoice("open", url))

    @on(Input.Changed, "#store-url")
    def _typed(self) -> None:
        self.query_one("#store-url-error", Static).update("")
