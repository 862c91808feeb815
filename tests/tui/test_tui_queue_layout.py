"""The queue screen's sweeps table: as tall as its rows in an area that fills the screen
(slopetui.tcss says why), and scrolled within that area when the sweeps do not fit."""

from __future__ import annotations

from textual.containers import Vertical
from textual.widgets import DataTable

from slopetui.tui.app import SlopeApp
from slopetui.tui.screens.queue import QueueScreen
from tests.support import submit_quick
from tests.tui.support import run, wait_until


def table_and_area(app: SlopeApp) -> tuple[DataTable, Vertical]:
    return (app.screen.query_one("#queue-table", DataTable),
            app.screen.query_one("#queue-area", Vertical))


async def queue_with_rows(pilot, app: SlopeApp, rows: int) -> tuple[DataTable, Vertical]:
    """The queue screen once its sweeps table shows ``rows`` sweeps: the table and its area."""
    await wait_until(pilot, lambda: app.db is not None)
    await pilot.press("2")
    await wait_until(pilot, lambda: isinstance(app.screen, QueueScreen)
                     and table_and_area(app)[0].row_count == rows)
    await pilot.pause(0.2)
    return table_and_area(app)


def test_few_sweeps_leave_the_area_below_the_table(db):
    submit_quick(db, 2)
    submit_quick(db, 2, tau=3.0)

    async def scenario():
        app = SlopeApp(db.display_url, start_workers=False, refresh_s=60.0)
        async with app.run_test(size=(80, 24)) as pilot:
            table, area = await queue_with_rows(pilot, app, 2)
            assert table.size.height == 3  # the header and two rows
            assert area.size.height > 10 and area.region.bottom == 23  # down to the footer

    run(scenario)


def test_many_sweeps_scroll_within_the_area(db):
    for i in range(30):
        submit_quick(db, 1, tau=1.0 + i)

    async def scenario():
        app = SlopeApp(db.display_url, start_workers=False, refresh_s=60.0)
        async with app.run_test(size=(80, 24)) as pilot:
            table, area = await queue_with_rows(pilot, app, 30)
            assert table.region.height == area.region.height < 31
            assert app.screen.max_scroll_y == 0  # the screen itself does not scroll
            await pilot.press(*["down"] * 29)  # to the last sweep (the oldest)
            await pilot.pause(0.2)
            assert table.cursor_row == 29 and table.scroll_y > 0

    run(scenario)
