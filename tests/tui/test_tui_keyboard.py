"""Pilot tests of the keyboard and its discoverability: the help screen (? and F1) made
from the bindings, the command palette's commands, the footer at 80 columns, quitting the
same way everywhere, and the way on when the store cannot be opened."""

from __future__ import annotations

import json

from textual.actions import parse
from textual.command import CommandList, CommandPalette
from textual.widgets import Input, Static, TextArea

from slopetui.sweeps.presets import PRESETS
from slopetui.tui.app import SlopeApp
from slopetui.tui.commands import SCREEN_NAMES, commands
from slopetui.tui.screens.error import StoreErrorScreen, store_url
from slopetui.tui.screens.help import HelpScreen
from slopetui.tui.screens.new_sweep import NewSweepScreen
from slopetui.tui.screens.run_detail import RunDetailScreen
from slopetui.tui.screens.sql import SqlScreen
from slopetui.tui.screens.sweeps import SweepsScreen
from tests.support import submit_quick
from tests.tui.support import run, wait_until


def app_for(db) -> SlopeApp:
    return SlopeApp(db.display_url, start_workers=False, refresh_s=0.2)


def screen_lines(app: SlopeApp) -> list[str]:
    """The screen as drawn, one string a row: what the user sees (Textual exports it only
    as SVG otherwise)."""
    return [strip.text for strip in app.screen._compositor.render_strips()]


def help_rows(app: SlopeApp) -> dict[str, str]:
    """The open help's rows: description -> keys."""
    assert isinstance(app.screen, HelpScreen)
    return {row.description: row.keys for row in app.screen.rows()}


def live_bindings(node, bindings) -> set[str]:
    """Descriptions of ``bindings`` (of ``node``, a screen or the app) whose action the
    node does not veto now (check_action)."""
    found = set()
    for binding in bindings:
        _, name, params = parse(binding.action)
        if not binding.system and node.check_action(name, params) is not False:
            found.add(binding.description)
    return found


async def open_palette_and_choose(app: SlopeApp, pilot, query: str, hit: str) -> None:
    """ctrl+p, type ``query``, wait until ``hit`` is the highlighted command, enter."""
    await pilot.press("ctrl+p")
    await wait_until(pilot, lambda: isinstance(app.screen, CommandPalette))
    app.screen.query_one(Input).value = query

    def highlighted() -> str:
        commands_list = app.screen.query_one(CommandList)
        index = commands_list.highlighted
        return "" if index is None else str(commands_list.get_option_at_index(index).prompt)

    await wait_until(pilot, lambda: hit in highlighted())
    await pilot.press("enter")


# -- help --------------------------------------------------------------------------------

def test_help_lists_every_key_of_the_sweeps_screen_hidden_ones_too_and_closes(db):
    submit_quick(db, 3)

    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            await wait_until(pilot, lambda: app.query_one("#sweep-table").row_count == 1)
            sweeps = app.screen
            expected = (live_bindings(sweeps, SweepsScreen.BINDINGS)
                        | live_bindings(app, SlopeApp.BINDINGS))
            await pilot.press("question_mark")
            await wait_until(pilot, lambda: isinstance(app.screen, HelpScreen))
            rows = help_rows(app)
            assert expected <= set(rows)
            # hidden from the footer, listed here: the app's mode keys, n and v
            assert {rows["New sweep"], rows["Compare"], rows["SQL"]} == {"n", "v", "3"}
            assert rows["Help"] == "? f1" and rows["Quit"] == "^q q"
            assert "Retry store" not in rows  # ctrl+o acts only when the store failed to open
            # drawn within 80x24: the first section's title shows
            assert any("This screen (Sweeps)" in line for line in screen_lines(app))
            await pilot.press("escape")
            await wait_until(pilot, lambda: app.screen is sweeps)
            await pilot.press("f1", "q")  # q closes the help, and does not quit
            await wait_until(pilot, lambda: app.screen is sweeps)
            assert app.return_code is None

    run(scenario)


def test_help_of_a_run_lists_its_tab_keys(db):
    submit_quick(db, 3)  # queued: the detail shows the run, nothing is recomputed
    run_id = 1

    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            await wait_until(pilot, lambda: app.db is not None)
            app.open_run(run_id)
            await wait_until(pilot, lambda: isinstance(app.screen, RunDetailScreen))
            detail = app.screen
            expected = live_bindings(detail, RunDetailScreen.BINDINGS)
            await pilot.press("question_mark")
            await wait_until(pilot, lambda: isinstance(app.screen, HelpScreen))
            rows = help_rows(app)
            assert expected <= set(rows)
            assert rows["Time"] == "t"  # a tab key the footer does not show
            assert app.screen.sections[0].title == "This screen (Run detail)"
            await pilot.press("question_mark")
            await wait_until(pilot, lambda: app.screen is detail)

    run(scenario)


def test_help_of_the_sql_console_lists_the_editor_keys(db):
    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            await pilot.press("3")
            await wait_until(pilot, lambda: isinstance(app.screen, SqlScreen)
                             and isinstance(app.focused, TextArea))
            console, editor = app.screen, app.focused
            await pilot.press("question_mark")  # typed: the editor has focus
            assert editor.text.endswith("?") and app.screen is console
            await pilot.press("f1")
            await wait_until(pilot, lambda: isinstance(app.screen, HelpScreen))
            rows = help_rows(app)
            assert "Cancel query" in rows  # hidden from the footer
            assert {"Run", "Schema/history", "Clear"} <= set(rows)
            assert rows["Help"] == "f1" and rows["Quit"] == "^q"  # ? and q go to the editor
            titles = [s.title for s in app.screen.sections]
            assert titles[0] == "This screen (SQL)"
            assert "The focused QueryEditor #sql-editor" in titles and titles[-1] == "Everywhere"
            assert rows["Leave editor"] == "esc/tab"  # how to leave it, in the footer too
            await pilot.press("q")
            await wait_until(pilot, lambda: app.screen is console)

    run(scenario)


# -- the palette -------------------------------------------------------------------------

def test_the_palette_opens_a_run_by_id(db):
    submit_quick(db, 3)  # runs 1 to 3

    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            await wait_until(pilot, lambda: app.db is not None)
            await open_palette_and_choose(app, pilot, "run 2", "Open run 2")
            await wait_until(pilot, lambda: isinstance(app.screen, RunDetailScreen))
            assert app.screen.run_id == 2

    run(scenario)


def test_the_palette_offers_each_preset_and_each_screen(db):
    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            await wait_until(pilot, lambda: app.db is not None)
            names = [c.name for c in commands(app, app.screen)]
            for preset in PRESETS:
                assert f"New sweep: {preset.figure}, {preset.title}" in names
            for mode in SlopeApp.MODES:
                assert f"Go to {SCREEN_NAMES[mode]}" in names
            assert {"New sweep", "Quit slopetui", "Compare the marked runs",
                    "Help: the keys of this screen", "Write this screen's figure"} <= set(names)
            # Textual's system commands stay, but for its Quit (the one above says more)
            system = [c.title for c in app.get_system_commands(app.screen)]
            assert "Theme" in system and "Keys" in system and "Quit" not in system
            # chosen in the palette: the form opens filled with the preset
            fig7b = next(p for p in PRESETS if p.key == "fig7b")
            name = f"New sweep: {fig7b.figure}, {fig7b.title}"
            await open_palette_and_choose(app, pilot, name, name)
            await wait_until(pilot, lambda: isinstance(app.screen, NewSweepScreen)
                             and app.screen.query_one("#x-param").value == "a")
            assert app.screen.query_one("#fixed-k").value == "12"
            await pilot.press("escape")
            await open_palette_and_choose(app, pilot, "Go to SQL console", "Go to SQL console")
            await wait_until(pilot, lambda: isinstance(app.screen, SqlScreen))

    run(scenario)


def test_the_palette_exports_the_selected_sweep_and_pauses_a_sweep_by_id(db, tmp_path):
    sweep = submit_quick(db, 3).sweep_id

    async def scenario():
        app = app_for(db)
        app.figure_folder = tmp_path
        async with app.run_test(size=(80, 24)) as pilot:
            await wait_until(pilot, lambda: app.screen.selected == sweep)
            for fmt in ("CSV", "JSON"):
                name = f"Export sweep {sweep} (selected) as {fmt}"
                await open_palette_and_choose(app, pilot, name, name)
            csv_file = tmp_path / f"sweep-{sweep}-runs.csv"
            json_file = tmp_path / f"sweep-{sweep}-runs.json"
            await wait_until(pilot, lambda: csv_file.exists() and json_file.exists())
            assert csv_file.read_text().splitlines()[0].startswith("id,sweep_id,")
            assert len(csv_file.read_text().splitlines()) == 4
            assert [r["sweep_id"] for r in json.loads(json_file.read_text())] == [sweep] * 3
            await open_palette_and_choose(app, pilot, f"pause sweep {sweep}", "Pause sweep")
            await wait_until(pilot, lambda: _status(db, sweep) == "paused")

    run(scenario)


def test_cancel_by_id_asks_about_a_known_sweep_and_says_a_failed_read(db, monkeypatch):
    """"cancel sweep 3" from the palette reads the sweep's progress in the background:
    a known sweep gets the question, an unknown one a notice, and a read that fails a
    notice too (a failed read ended the application with a traceback)."""
    from slopetui.tui.screens import confirm

    sweep = submit_quick(db, 3).sweep_id
    status = _status(db, sweep)

    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            await wait_until(pilot, lambda: app.db is not None)
            confirm.ask_then_control_id(app, "cancel", sweep)
            await wait_until(pilot, lambda: isinstance(app.screen, confirm.ConfirmScreen))
            await pilot.press("n")
            await wait_until(pilot, lambda: isinstance(app.screen, SweepsScreen))

            def notice_after(start) -> str:
                before = len(app._notifications)
                start()
                return wait_until(pilot, lambda: len(app._notifications) > before)

            await notice_after(lambda: confirm.ask_then_control_id(app, "cancel", sweep + 9))
            assert list(app._notifications)[-1].message == f"cancel sweep {sweep + 9}: no such sweep"

            def fail(*_args):
                raise OSError("disk I/O error")
            monkeypatch.setattr(confirm, "sweep_progress", fail)
            monkeypatch.setattr("slopetui.sweeps.progress.sweep_progress", fail)  # where it was read
            await notice_after(lambda: confirm.ask_then_control_id(app, "cancel", sweep))
            assert list(app._notifications)[-1].message \
                == f"cancel sweep {sweep}: OSError: disk I/O error"
            monkeypatch.undo()
            assert app.is_running and _status(db, sweep) == status  # not cancelled

    run(scenario)


def _status(db, sweep_id: int) -> str:
    from slopetui.sweeps.progress import sweep_progress
    return next(p.status for p in sweep_progress(db) if p.id == sweep_id)


# -- footer and quitting -----------------------------------------------------------------

def test_the_footer_at_80_columns_shows_help_and_quit(db):
    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            await wait_until(pilot, lambda: app.db is not None)
            await pilot.pause()
            footer = screen_lines(app)[-1]
            assert "? Help" in footer and "^q Quit" in footer and "^p palette" in footer
            for hidden in ("New sweep", "Compare", "Sweeps", "Queue", "Branches"):
                assert hidden not in footer
            await pilot.press("3")
            await wait_until(pilot, lambda: isinstance(app.screen, SqlScreen))
            await pilot.pause()
            footer = screen_lines(app)[-1]  # "?" goes to the editor there: F1 opens the help
            assert "f1 Help" in footer and "^q Quit" in footer

    run(scenario)


def test_ctrl_q_quits_the_sql_console_and_q_is_typed_into_its_editor(db):
    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            await pilot.press("3")
            await wait_until(pilot, lambda: isinstance(app.screen, SqlScreen)
                             and isinstance(app.focused, TextArea))
            editor = app.focused
            await pilot.press("q")
            await pilot.pause()
            assert editor.text.endswith("q") and app.return_code is None
            await pilot.press("ctrl+q")
            await wait_until(pilot, lambda: app.return_code is not None)
        assert app.return_code == 0

    run(scenario)


def test_q_quits_from_the_sweeps_screen(db):
    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            await wait_until(pilot, lambda: app.db is not None)
            assert isinstance(app.screen, SweepsScreen)
            await pilot.press("q")
            await wait_until(pilot, lambda: app.return_code is not None)
        assert app.return_code == 0

    run(scenario)


# -- a store that cannot be opened -------------------------------------------------------

def test_retry_opens_the_store_once_its_folder_exists(tmp_path):
    folder = tmp_path / "not-yet"

    async def scenario():
        app = SlopeApp(f"sqlite:///{folder}/store.db", start_workers=False, refresh_s=0.2)
        async with app.run_test(size=(80, 24)) as pilot:
            await wait_until(pilot, lambda: isinstance(app.screen, StoreErrorScreen)
                             and app.focused is not None)  # mounted
            assert "not-yet" in str(app.screen.query_one("#error-cause", Static).render())
            await pilot.press("escape")  # closed without a choice: no store, and it says so
            await wait_until(pilot, lambda: isinstance(app.screen, SweepsScreen))
            status = app.store_status.plain
            assert "could not be opened" in status and "not-yet" in status
            assert "ctrl+o" in status
            await pilot.press("r")  # the sweeps screen's key (resume): not a retry
            assert app.db is None
            folder.mkdir()
            await pilot.press("ctrl+o")
            await wait_until(pilot, lambda: isinstance(app.screen, StoreErrorScreen)
                             and app.focused is not None)
            await pilot.press("r")
            await wait_until(pilot, lambda: app.db is not None)
            assert app.store_error is None and isinstance(app.screen, SweepsScreen)
            await wait_until(pilot, lambda: "No sweeps yet" in str(
                app.screen.query_one("#diagram-empty", Static).render()))
        assert (folder / "store.db").exists()

    run(scenario)


def test_another_store_is_checked_then_opened(tmp_path):
    other = tmp_path / "other.db"

    async def scenario():
        app = SlopeApp(f"sqlite:///{tmp_path}/missing/store.db", start_workers=False,
                       refresh_s=0.2)
        async with app.run_test(size=(80, 24)) as pilot:
            await wait_until(pilot, lambda: isinstance(app.screen, StoreErrorScreen)
                             and app.focused is not None)  # mounted
            dialog = app.screen
            await pilot.press("o")
            field = dialog.query_one("#store-url", Input)
            await wait_until(pilot, lambda: app.focused is field)
            field.value = str(tmp_path / "nowhere" / "x.db")
            await pilot.press("enter")
            await pilot.pause()
            assert app.screen is dialog and app.db is None  # refused before it is tried
            assert "no folder" in str(dialog.query_one("#store-url-error", Static).render())
            field.value = str(other)
            await pilot.press("enter")
            await wait_until(pilot, lambda: app.db is not None)
            assert app.db.path == other.resolve()

    run(scenario)


def test_the_sweeps_screen_says_the_store_could_not_be_opened(tmp_path):
    async def scenario():
        app = SlopeApp(f"sqlite:///{tmp_path}/missing/store.db", start_workers=False,
                       refresh_s=0.2)
        async with app.run_test(size=(80, 24)) as pilot:
            await wait_until(pilot, lambda: isinstance(app.screen, StoreErrorScreen)
                             and app.focused is not None)
            await pilot.press("escape")
            await wait_until(pilot, lambda: isinstance(app.screen, SweepsScreen))
            empty = app.screen.query_one("#diagram-empty", Static)
            await wait_until(pilot, lambda: "could not be opened" in str(empty.render()))
            assert "ctrl+o" in str(empty.render())
            # the other screens with data say so too, not "opening" forever
            await pilot.press("4")
            await wait_until(pilot, lambda: app.screen.query("#branch-detail")
                             and "could not be opened" in str(
                                 app.screen.query_one("#branch-detail", Static).render()))
            await pilot.press("3")
            await wait_until(pilot, lambda: app.screen.query("#sql-status")
                             and "could not be opened" in str(
                                 app.screen.query_one("#sql-status", Static).render()))

    run(scenario)


def test_store_url_takes_a_url_or_a_path(tmp_path):
    assert store_url(f" {tmp_path}/a.db ") == f"sqlite:///{tmp_path}/a.db"
    assert store_url("postgresql+psycopg://host/db") == "postgresql+psycopg://host/db"
    for bad, says in (("", "type a database URL"), (str(tmp_path), "is a folder"),
                      (f"sqlite:///{tmp_path}/no/a.db", "no folder"),
                      ("://x", "not a SQLAlchemy database URL")):
        try:
            store_url(bad)
        except ValueError as exc:
            assert says in str(exc)
        else:
            raise AssertionError(f"{bad!r} was accepted")
