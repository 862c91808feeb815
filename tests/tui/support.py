"""Helpers for the Pilot tests of the application (tests/tui/)."""

from __future__ import annotations

import asyncio
import time
from collections.abc import Callable

from slopetui.tui.app import SlopeApp
from slopetui.tui.screens.new_sweep import NewSweepScreen


async def wait_until(pilot, predicate: Callable[[], bool], timeout: float = 20.0) -> None:
    """Let the app run until predicate() holds (thread workers deliver asynchronously)."""
    deadline = time.monotonic() + timeout
    while not predicate():
        if time.monotonic() > deadline:
            raise AssertionError("the app did not reach the expected state")
        await pilot.pause(0.05)


def run(scenario) -> None:
    asyncio.run(scenario())


async def open_form(app: SlopeApp, pilot) -> NewSweepScreen:
    """Press n once the store is open; return the form once it has composed."""
    await wait_until(pilot, lambda: app.db is not None)
    await pilot.press("n")
    await wait_until(pilot, lambda: isinstance(app.screen, NewSweepScreen)
                     and bool(app.screen.query("#form-buttons")))
    return app.screen


def fill(app, values: dict[str, str]) -> None:
    for widget_id, value in values.items():
        app.screen.query_one(f"#{widget_id}").value = value
