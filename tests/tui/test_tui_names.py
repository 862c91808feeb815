"""Names with control characters or markup, shown escaped in the application and never as
Rich markup (the rest of the rule: tests/unit/test_input_names.py)."""

from __future__ import annotations

from slopetui.sweeps.spec import parse_spec
from slopetui.sweeps.submit import submit
from tests.support import QUICK_SOLVER
from tests.tui.support import run, wait_until


def test_the_application_shows_stored_names_escaped_and_never_as_markup(db, evil_sweep):
    """A str cell of a DataTable is Rich markup: "[red]x" drew a red x, and "[/oops]"
    raised a MarkupError that stopped the screen."""
    for name in ("[red]x", "[/oops]"):
        submit(db, parse_spec({"name": name, "x": {"param": "k", "start": 4, "stop": 12,
                                                   "num": 2}, "solver": QUICK_SOLVER}))
    from slopetui.tui.app import SlopeApp
    from slopetui.tui.screens.queue import QueueScreen

    async def scenario():
        app = SlopeApp(db.display_url, start_workers=False, refresh_s=0.2)
        async with app.run_test(size=(100, 30)) as pilot:
            table = app.query_one("#sweep-table")
            await wait_until(pilot, lambda: table.row_count == 3)
            await pilot.pause(0.2)
            screen = app.export_screenshot()
            assert "[red]x" in screen and "[/oops]" in screen and "\\x1b[2J" in screen
            await pilot.press("2")
            await wait_until(pilot, lambda: isinstance(app.screen, QueueScreen))
            queue = app.screen.query_one("#queue-table")
            await wait_until(pilot, lambda: queue.row_count == 3)
            await pilot.pause(0.2)
            screen = app.export_screenshot()
            assert "[red]x" in screen and "[/oops]" in screen and "\\x1b[2J" in screen

    run(scenario)


def test_a_store_failure_quoting_stored_text_is_shown_escaped_and_not_as_markup(db):
    """A worker's failed read is one notification: its error may quote stored text (an
    escape sequence; brackets that would be markup, or a MarkupError)."""
    from slopetui.tui.app import SlopeApp
    from slopetui.tui.messages import StoreFailed

    async def scenario():
        app = SlopeApp(db.display_url, start_workers=False, refresh_s=0.2)
        async with app.run_test(size=(100, 30)) as pilot:
            await pilot.pause(0.2)
            app.screen.post_message(StoreFailed("read the queue",
                                                "ValueError: '\x1b]0;owned\x07 [/oops]'"))
            await wait_until(pilot, lambda: len(app._notifications) > 0)
            note = list(app._notifications)[-1]
            assert note.message == "could not read the queue: ValueError: '\\x1b]0;owned\\x07 [/oops]'"
            assert not note.markup
            await pilot.pause(0.2)
            assert "\x1b]" not in app.export_screenshot()

    run(scenario)
