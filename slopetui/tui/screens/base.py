"""The one typed way for a screen to reach the application and its store.

Screens derive from ``SlopeScreen`` instead of ``Screen``: ``self.app`` is then typed as
``SlopeApp`` (what Posting gets with ``cast("Posting", super().app)``), and ``self.db`` is
the store, or None until the app has opened it (``SlopeApp.open_store`` runs in a thread
worker).
No ``getattr(self.app, "db", None)``, no ``# type: ignore[attr-defined]``.

Textual declares its own ``app`` this way (``textual.getters.app``) for the type checker
only; at run time Screen's property already returns the SlopeApp. (Declared for real,
``getters.app(SlopeApp)`` would need the class when the screen's class is defined, and
``slopetui.tui.app`` imports the screens.)
"""

from __future__ import annotations

from typing import TYPE_CHECKING, TypeVar

from textual import on
from textual.screen import Screen

from slopetui.tui.messages import StoreFailed

if TYPE_CHECKING:
    from textual import getters

    from slopetui.store.database import Database
    from slopetui.tui.app import SlopeApp

ResultT = TypeVar("ResultT")


class SlopeScreen(Screen[ResultT]):
    """A screen of SlopeApp."""

    if TYPE_CHECKING:  # at run time Screen's own property returns the same object
        app = getters.app(SlopeApp)

    @property
    def db(self) -> Database | None:
        """The store, or None while the app is still opening it."""
        return self.app.db

    def refresh_data(self) -> None:
        """The app calls this on the screen in view once the store is open and after it
        changed a sweep; a screen with live data reloads it (this one has none)."""

    @on(StoreFailed)
    def show_store_failure(self, failed: StoreFailed) -> None:
        """A worker's database or file call failed: one notification, never a traceback
        (every screen shows it the same way)."""
        failed.stop()  # shown here; the app need not show it again
        self.notify(f"could not {failed.action}: {failed.error}", severity="error", timeout=8)
