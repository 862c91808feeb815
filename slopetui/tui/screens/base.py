"""The one typed way for a screen to reach the application and its store.

Screens derive from ``SlopeScreen`` instead of ``Screen``: ``self.app`` is then typed as
``SlopeApp`` (what Posting gets with ``cast("Posting", super().app)``), and ``self.db`` is
the store, or None until the app has opened it (``SlopeApp.open_store`` runs in a thread
worker).
No ``getattr(self.app, "db", None)``, no ``# type: ignore[attr-defined]``.

A screen with live data (sweeps, queue, branches) reloads it every ``app.refresh_s``
seconds while it is in view, and not at all while another screen covers it (a mode
switched away from, a screen pushed on top): ``refresh_while_shown`` starts the timer, the
screen's suspend pauses it, and its resume restarts it and catches up as soon as the
screen is drawn: a hidden sweeps screen would otherwise re-read its 10,000 runs every 2 s
behind the queue screen.

Textual declares its own ``app`` this way (``textual.getters.app``) for the type checker
only; at run time Screen's property already returns the SlopeApp. (Declared for real,
``getters.app(SlopeApp)`` would need the class when the screen's class is defined, and
``slopetui.tui.app`` imports the screens.)
"""

from __future__ import annotations

from typing import TYPE_CHECKING, TypeVar

from textual import events, on
from textual.screen import Screen
from textual.timer import Timer

from slopetui.tui import garbage
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

    #: The timer of refresh_while_shown, and whether another screen covers this one.
    _live_timer: Timer | None = None
    hidden = False

    @property
    def db(self) -> Database | None:
        """The store, or None while the app is still opening it."""
        return self.app.db

    def refresh_data(self) -> None:
        """The app calls this on the screen in view once the store is open and after it
        changed a sweep; a screen with live data reloads it (this one has none)."""

    def refresh_while_shown(self) -> None:
        """Reload the screen's data now and every ``app.refresh_s`` seconds while it is in
        view (module docstring); call once, when mounted."""
        self._live_timer = self.set_interval(self.app.refresh_s, self.refresh_data)
        self.refresh_data()

    @on(events.ScreenSuspend)
    def _pause_refresh(self) -> None:
        self.hidden = True
        if self._live_timer is not None:
            self._live_timer.pause()

    @on(events.ScreenResume)
    def _resume_refresh(self) -> None:
        if not self.hidden:  # the first resume, when shown first: on_mount loaded it
            return
        self.hidden = False
        # once the screen is drawn: work done meanwhile would delay the drawing (a read in
        # a thread takes the interpreter from it too). A switch of modes must not hold
        # updates for this to hold: SlopeApp.switch_mode says why.
        self.call_after_refresh(self._back_in_view)

    def _back_in_view(self) -> None:
        garbage.collect()  # what the switch left (slopetui.tui.garbage)
        if self._live_timer is not None:
            self._live_timer.resume()
            self.refresh_data()  # catch up with what changed while hidden

    @on(StoreFailed)
    def show_store_failure(self, failed: StoreFailed) -> None:
        """A worker's database or file call failed: one notification, never a traceback
        (every screen shows it the same way)."""
        failed.stop()  # shown here; the app need not show it again
        # the error may quote stored text: escaped, and never read as markup
        self.app.notify_text(f"could not {failed.action}: {failed.error}", severity="error",
                             timeout=8)
