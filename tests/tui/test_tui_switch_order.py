"""A screen switched back to is drawn before it catches up.

Its catch-up (a garbage collection and the reload of its data in a thread,
SlopeScreen._back_in_view) ran before the drawing while Textual held updates for 50 ms
on every switch of modes; SlopeApp.switch_mode holds them only for a screen not built
yet. The drawing is seen where Textual writes it (App._display, which drops what it is
given while updates are held), the catch-up where the screen starts it (refresh_data).
"""

from __future__ import annotations

from textual.app import App
from textual.screen import Screen

from slopetui.tui.app import SlopeApp
from slopetui.tui.screens.branches import BranchesScreen
from slopetui.tui.screens.queue import QueueScreen
from slopetui.tui.screens.sweeps import SweepsScreen
from tests.support import finish_all, submit_quick
from tests.tui.support import run, wait_until


def test_a_screen_switched_back_to_is_drawn_before_it_catches_up(db, monkeypatch):
    submit_quick(db, 3)
    finish_all(db)
    events: list[tuple[str, str]] = []
    display = App._display

    def shown(app: App, screen: Screen, update: object) -> None:
        # what Textual writes to the terminal: not while it holds updates
        if update is not None and not app._batch_count and screen is app.screen:
            events.append(("drawn", type(screen).__name__))
        display(app, screen, update)

    monkeypatch.setattr(App, "_display", shown)
    for cls in (QueueScreen, BranchesScreen, SweepsScreen):
        def catch_up(screen, real=cls.refresh_data) -> None:
            events.append(("catch-up", type(screen).__name__))
            real(screen)
        monkeypatch.setattr(cls, "refresh_data", catch_up)

    async def scenario():
        app = SlopeApp(db.display_url, start_workers=False, refresh_s=60.0)
        async with app.run_test(size=(120, 40)) as pilot:
            await wait_until(pilot, lambda: app.db is not None)
            for key in ("2", "1", "4", "1"):  # the first visits build the screens
                await pilot.press(key)
                await pilot.pause(0.3)
            for key, cls in (("2", QueueScreen), ("1", SweepsScreen), ("4", BranchesScreen)):
                events.clear()
                await pilot.press(key)
                await wait_until(pilot, lambda cls=cls: ("catch-up", cls.__name__) in events)
                assert events.index(("drawn", cls.__name__)) < \
                       events.index(("catch-up", cls.__name__)), events

    run(scenario)


def test_only_a_screen_not_built_yet_holds_the_updates(db, monkeypatch):
    """The first visit of a mode composes its screen behind Textual's hold on updates;
    later visits draw at once."""
    holds: list[int] = []
    delay = App.delay_update

    def counted(app: App, *args, **kwargs) -> None:
        holds.append(1)
        delay(app, *args, **kwargs)

    monkeypatch.setattr(App, "delay_update", counted)

    async def scenario():
        app = SlopeApp(db.display_url, start_workers=False, refresh_s=60.0)
        held = []
        async with app.run_test(size=(120, 40)) as pilot:
            await wait_until(pilot, lambda: app.db is not None)
            for key in ("2", "1", "2", "4", "1", "4"):
                before = len(holds)
                await pilot.press(key)
                await pilot.pause(0.2)
                held.append(len(holds) > before)
        # the queue and the branches the first time only; the sweeps screen is the first
        assert held == [True, False, False, True, False, False]

    run(scenario)
