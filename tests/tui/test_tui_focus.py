"""Focus you can see: in the SQL editor and the form the digits and q
are typed into the field, so the field that has the keys is lit and the footer says how
to leave it (escape or tab)."""

from __future__ import annotations

from textual.widget import Widget

from slopetui.tui.screens.new_sweep import NewSweepScreen
from slopetui.tui.screens.sql import SqlScreen
from slopetui.tui.screens.sweeps import SweepsScreen
from slopetui.tui.widgets.query_editor import RESTING, TYPING, QueryEditor
from tests.tui.support import open_form, run, wait_until
from tests.tui.test_tui_app import app_for
from tests.tui.test_tui_keyboard import screen_lines


def background(widget: Widget):
    """The colour the widget is drawn on (its own, over its containers')."""
    return widget.background_colors[1]


def test_the_sql_editor_says_it_has_the_keys_and_escape_leaves_it(db):
    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            await pilot.press("3")
            await wait_until(pilot, lambda: isinstance(app.screen, SqlScreen)
                             and isinstance(app.focused, QueryEditor))
            editor = app.focused
            await pilot.pause()
            footer = screen_lines(app)[-1]
            assert "esc/tab Leave editor" in footer and "^q Quit" in footer
            assert editor.border_subtitle == TYPING
            focused_border = editor.styles.border_top[1]
            await pilot.press("1")  # typed into the query: the footer said so
            assert isinstance(app.screen, SqlScreen) and editor.text.endswith("1")
            await pilot.press("escape")
            await wait_until(pilot, lambda: not editor.has_focus)
            await pilot.pause()
            footer = screen_lines(app)[-1]
            assert "Leave editor" not in footer and "esc Editor" in footer
            assert editor.border_subtitle == RESTING
            assert editor.styles.border_top[1] != focused_border
            await pilot.press("1")  # out of the editor: the key switches screens again
            await wait_until(pilot, lambda: isinstance(app.screen, SweepsScreen))

    run(scenario)


def test_the_form_lights_the_field_with_the_keys_and_says_tab_moves_on(db):
    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            form = await open_form(app, pilot)
            name, levels = form.query_one("#name"), form.query_one("#adaptive-levels")
            stop = form.query_one("#x-stop")
            assert app.focused is name
            await pilot.pause()
            assert "tab Next field" in screen_lines(app)[-1]
            # the field with the keys, and its row, stand out from the others
            assert background(name) != background(stop)
            assert background(name.parent) != background(stop.parent)
            await pilot.press("1", "q")  # typed into the name
            assert isinstance(app.screen, NewSweepScreen) and name.value == "1q"
            await pilot.press("tab")  # the stop rule, beside the name
            await wait_until(pilot, lambda: app.focused is form.query_one("#solver-stop"))
            await pilot.press("tab")
            await wait_until(pilot, lambda: app.focused is levels)
            await pilot.pause()
            assert background(levels) != background(name)
            assert background(levels) != background(stop)

    run(scenario)
