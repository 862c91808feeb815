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


def test_the_applications_own_notifications_quoting_a_cause_are_escaped_and_not_markup(db):
    """The application's notices of a failed pool start, sweep control, figure or export
    quote a cause or a path that may hold stored text: escaped, and never read as markup
    (a "[/oops]" in a cause raised a MarkupError; an ESC reached the terminal)."""
    from slopetui.tui.app import SlopeApp

    cause = "ValueError: '\x1b]0;owned\x07 [/oops] \u202e'"
    shown = "ValueError: '\\x1b]0;owned\\x07 [/oops] \\u202e'"

    async def scenario():
        app = SlopeApp(db.display_url, start_workers=False, refresh_s=0.2)
        async with app.run_test(size=(100, 30)) as pilot:
            await pilot.pause(0.2)
            for message, text in [
                    (app.PoolFailed(cause), f"could not start workers: {shown}"),
                    (app.SweepControlFailed("pause", 3, cause), f"pause sweep 3: {shown}"),
                    (app.FigureFailed(cause), f"could not write the figure: {shown}"),
                    (app.SweepExported(cause), shown),
                    (app.ExportFailed(3, cause), f"could not export sweep 3: {shown}")]:
                before = len(app._notifications)
                app.post_message(message)
                await wait_until(pilot, lambda n=before: len(app._notifications) > n)
                note = list(app._notifications)[-1]
                assert note.message == text
                assert not note.markup
            await pilot.pause(0.2)
            assert "\x1b]" not in app.export_screenshot()

    run(scenario)
