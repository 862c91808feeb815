"""What the application keeps for a tracker (Pilot, 80x24): marks that survive a restart,
a sweep renamed, tagged and annotated with e, checked while typing, and two sweeps' specs
side by side from the palette."""

from __future__ import annotations

import time

import pytest
from textual.widgets import Button, DataTable, Input, Static, TextArea

import slopetui.tui.app as app_module
from slopetui.store.database import Database
from slopetui.store.runs.marks import marked_runs, set_mark
from slopetui.sweeps import annotations
from slopetui.tui.screens.confirm import ConfirmScreen
from slopetui.tui.screens.spec_compare import SpecCompareScreen, compare_sweeps
from slopetui.tui.screens.sweep_labels import SweepLabelsScreen
from slopetui.tui.widgets.phase_grid import PhaseGrid
from tests.support import finish_all, submit_quick
from tests.tui.support import run, wait_until
from tests.tui.test_tui_app import app_for, plane
from tests.tui.test_tui_keyboard import open_palette_and_choose
from tests.unit.test_annotations import hostile_key


def test_marks_survive_a_restart(db: Database) -> None:
    plane(db, nx=4, ny=2)
    finish_all(db)
    marked: list[int] = []

    async def first_session() -> None:
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            grid = app.query_one(PhaseGrid)
            await wait_until(pilot, lambda: grid.data is not None)
            await pilot.press("d", "m")
            marked.append(grid.cursor_run()[0])
            await pilot.press("right", "m", "right", "m", "left", "m")  # the second unmarked
            marked.append(grid.cursor_run()[0] + 1)
            await wait_until(pilot, lambda: marked_runs(db) == tuple(marked))
            assert app.marked == marked

    async def second_session() -> None:
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            await wait_until(pilot, lambda: app.marked == marked)
            await pilot.press("v")  # two marked: the compare screen opens on them
            await wait_until(pilot, lambda: type(app.screen).__name__ == "CompareScreen")
            assert app.screen.run_ids == marked

    run(first_session)
    run(second_session)


def test_marks_reach_the_store_in_the_order_pressed(db: Database,
                                                   monkeypatch: pytest.MonkeyPatch) -> None:
    """m then m on one run leaves it unmarked in the store even when the first write is the
    slower (a busy store); the list the last write returns is the one shown, another
    application's mark with it."""
    plane(db, nx=4, ny=2)
    finish_all(db)
    calls: list[bool] = []

    def slow_first(db_: Database, run_id: int, marked: bool) -> tuple[int, ...]:
        calls.append(marked)
        if marked:
            time.sleep(0.5)
        return set_mark(db_, run_id, marked)

    monkeypatch.setattr(app_module, "set_mark", slow_first)

    async def scenario() -> None:
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            grid = app.query_one(PhaseGrid)
            await wait_until(pilot, lambda: grid.data is not None)
            await pilot.press("d", "m", "m")  # mark, then unmark the same run
            await wait_until(pilot, lambda: len(calls) == 2)
            await pilot.pause(1.0)  # both writes done: the slow one takes 0.5 s
            assert (app.marked, marked_runs(db)) == ([], ())
            other = grid.cursor_run()[0] + 1
            set_mark(db, other, True)  # another application marks a run
            await pilot.press("m")
            mine = grid.cursor_run()[0]
            await wait_until(pilot, lambda: app.marked == [other, mine])
            assert marked_runs(db) == (other, mine)

    run(scenario)


def test_e_renames_tags_and_annotates_the_selected_sweep(db: Database) -> None:
    sweep = plane(db, nx=3, ny=2)
    annotations.add_tags(db, sweep, ["old"])

    async def scenario() -> None:
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            await wait_until(pilot, lambda: app.db is not None and app.query_one(PhaseGrid).data
                             is not None)
            await pilot.press("e")
            await wait_until(pilot, lambda: isinstance(app.screen, SweepLabelsScreen))
            modal = app.screen
            assert modal.query_one("#labels-tags", Input).value == "old"
            await pilot.pause()
            assert modal.query_one("#labels-save", Button).region.bottom <= 24  # at 80x24 too
            modal.query_one("#labels-name", Input).value = "the (k, tau) plane"
            tags = modal.query_one("#labels-tags", Input)
            tags.value = "paper bad,tag"
            await pilot.pause()
            error = str(modal.query_one("#labels-error", Static).render())
            assert error.startswith("tags: 'bad,tag' is not a tag: allowed 1 to 32 letters")
            assert modal.query_one("#labels-save", Button).disabled
            await pilot.press("ctrl+s")  # refused while a field is not allowed
            assert app.screen is modal
            tags.value = "Paper fig4"
            modal.query_one("#labels-note", TextArea).text = "coarse first pass\nredo at dt/2"
            await pilot.pause()
            assert str(modal.query_one("#labels-error", Static).render()) == ""
            await pilot.press("ctrl+s")
            await wait_until(pilot, lambda: annotations.labels(db, sweep).tags == ("fig4", "paper"))
            saved = annotations.labels(db, sweep)
            assert (saved.name, saved.note) == ("the (k, tau) plane", "coarse first pass\nredo at dt/2")
            await wait_until(pilot, lambda: any(n.message.startswith(f"sweep {sweep} saved")
                                                for n in app._notifications))

    run(scenario)


def test_the_palette_compares_two_sweeps_specs(db: Database) -> None:
    first = submit_quick(db, 3).sweep_id
    second = submit_quick(db, 4, tau=3.0).sweep_id

    async def scenario() -> None:
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            await wait_until(pilot, lambda: app.db is not None)
            await open_palette_and_choose(app, pilot, f"compare sweeps {first} {second}",
                                          f"Compare the specs of sweeps {first} and {second}")
            await wait_until(pilot, lambda: isinstance(app.screen, SpecCompareScreen))
            screen = app.screen
            title = str(screen.query_one("#spec-title", Static).render())
            assert f"2 of {len(screen.comparison.settings)} settings differ" in title
            table = screen.query_one("#spec-table", DataTable)
            assert table.row_count == len(screen.comparison.settings)
            await pilot.press("d")
            rows = [[str(c) for c in table.get_row_at(i)] for i in range(table.row_count)]
            assert rows == [["*", "fixed.tau", "2", "3"], ["*", "x.num", "3", "4"]]
            await pilot.press("escape")
            assert not isinstance(app.screen, SpecCompareScreen)
            await open_palette_and_choose(app, pilot, f"compare sweeps {first} 99",
                                          f"Compare the specs of sweeps {first} and 99")
            await wait_until(pilot, lambda: any("no sweep with id 99" in n.message
                                                for n in app._notifications))

    run(scenario)


def test_a_spec_key_is_drawn_escaped(db: Database) -> None:
    first, second = submit_quick(db, 3).sweep_id, submit_quick(db, 4).sweep_id
    hostile_key(db, first)

    async def scenario() -> None:
        app = app_for(db)
        async with app.run_test(size=(120, 40)) as pilot:
            await wait_until(pilot, lambda: app.db is not None)
            compare_sweeps(app, first, second)
            await wait_until(pilot, lambda: isinstance(app.screen, SpecCompareScreen))
            await pilot.pause()
            screen = app.export_screenshot()
            assert not any(ch in screen for ch in ("\x1b", "\x07", "\u202e"))
            assert "fixed.\\x1b]0;owned\\x07" in screen

    run(scenario)


def test_ctrl_q_in_the_labels_modal_asks_before_losing_what_was_typed(db: Database) -> None:
    plane(db, nx=3, ny=2)

    async def scenario() -> None:
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            await wait_until(pilot, lambda: app.db is not None
                             and app.query_one(PhaseGrid).data is not None)
            await pilot.press("e")
            await wait_until(pilot, lambda: isinstance(app.screen, SweepLabelsScreen))
            labels = app.screen
            labels.query_one("#labels-note", TextArea).text = "two paragraphs of findings"
            await pilot.pause()
            await pilot.press("ctrl+q")
            await wait_until(pilot, lambda: isinstance(app.screen, ConfirmScreen))
            assert app.return_code is None
            assert "'s note is not saved" in app.screen.question
            await pilot.press("escape")  # keep editing: the modal and the note are there
            await wait_until(pilot, lambda: app.screen is labels)
            assert labels.query_one("#labels-note", TextArea).text == "two paragraphs of findings"
            labels.query_one("#labels-note", TextArea).text = ""
            assert labels.unsaved() is None  # as opened again: ctrl+q quits at once

    run(scenario)
