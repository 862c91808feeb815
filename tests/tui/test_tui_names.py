"""Names with control characters or markup, shown escaped in the application and never as
Rich markup (the rest of the rule: tests/unit/test_input_names.py)."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

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


def test_the_applications_own_notifications_quoting_a_cause_are_escaped_and_not_markup(
        db, monkeypatch):
    """The application's notices of a failed pool start, sweep control, figure or export,
    and of an export written, quote a cause or a path that may hold stored text: escaped,
    and never read as markup (a "[/oops]" in a cause raised a MarkupError; an ESC reached
    the terminal). Each action runs as the application runs it, in the background."""
    from slopetui.sweeps import control, export_files
    from slopetui.tui import app as app_module
    from slopetui.tui import figure_writing
    from slopetui.tui.app import SlopeApp

    cause = "'\x1b]0;owned\x07 [/oops] \u202e'"
    shown = "'\\x1b]0;owned\\x07 [/oops] \\u202e'"

    def fail(*_args, **_options):
        raise ValueError(cause)

    for module, name in [(app_module, "attach_pool"), (control, "apply"),
                         (figure_writing, "write_sweep_figure"), (export_files, "export_sweep")]:
        monkeypatch.setattr(module, name, fail)

    def exported(*_args, **_options):
        return export_files.Exported(Path(cause), 2)

    async def scenario():
        app = SlopeApp(db.display_url, start_workers=True, refresh_s=0.2)
        async with app.run_test(size=(100, 30)) as pilot:

            async def notice(start) -> str:
                before = len(app._notifications)
                start()
                await wait_until(pilot, lambda: len(app._notifications) > before)
                note = list(app._notifications)[-1]
                assert not note.markup
                return note.message

            # the pool is found or started once the store is open
            assert await notice(lambda: None) == f"could not start workers: {shown}"
            assert await notice(lambda: app.control_sweep("pause", 3)) == f"pause sweep 3: {shown}"
            assert await notice(lambda: app.write_sweep_figure(SimpleNamespace(id=3))) \
                == f"could not write the figure: ValueError: {shown}"
            assert await notice(lambda: app.export_sweep(3, "csv")) \
                == f"could not export sweep 3: ValueError: {shown}"
            monkeypatch.setattr(export_files, "export_sweep", exported)
            assert await notice(lambda: app.export_sweep(3, "csv")) \
                == f"2 runs of sweep 3 written to {shown}"
            await pilot.pause(0.2)
            assert "\x1b]" not in app.export_screenshot()

    run(scenario)
