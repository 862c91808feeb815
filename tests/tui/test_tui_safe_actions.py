"""Safe actions and honest states on the sweeps and queue screens (Pilot): cancel and
delete ask first in a modal (n and escape keep, y acts), resume queues a cancelled
sweep's runs again, a sweep whose runs all failed is a red bar at 0% (not a full green
one), the name column takes the width the screen has, and the screens' own footer keys
fit beside the app's at 80 columns.

No pytest-asyncio: each scenario runs with asyncio.run (tests/tui/support.py).
"""

from __future__ import annotations

from rich.text import Text
from sqlalchemy import func, select, update

from slopetui.store.database import Database
from slopetui.store.models import Run, Sweep
from slopetui.sweeps.spec import parse_spec
from slopetui.sweeps.submit import submit
from slopetui.tui.app import SlopeApp
from slopetui.tui.screens.confirm import ConfirmScreen
from slopetui.tui.screens.queue import QueueScreen
from slopetui.tui.screens.sweeps import (
    BAR_CELLS,
    BAR_WIDTH,
    NAME_COLUMN,
    NAME_MIN,
    SweepsScreen,
    progress_bar,
)
from tests.support import QUICK_SOLVER, claim_one, submit_quick
from tests.tui.support import run, wait_until
from tests.tui.test_tui_app import app_for
from tests.tui.test_tui_queue_layout import queue_with_rows

LONG_NAME = "a (k, tau) plane at delta = 0.1, every point computed twice over"


def statuses(db: Database, sweep_id: int) -> dict[str, int]:
    with db.sessions() as s:
        return dict(s.execute(select(Run.status, func.count()).where(Run.sweep_id == sweep_id)
                              .group_by(Run.status)).all())


def sweep_status(db: Database, sweep_id: int) -> str | None:
    with db.sessions() as s:
        sweep = s.get(Sweep, sweep_id)
        return None if sweep is None else sweep.status


def named(db: Database, name: str, n: int = 3) -> int:
    spec = parse_spec({"name": name, "x": {"param": "k", "start": 4, "stop": 12, "num": n},
                       "solver": QUICK_SOLVER})
    return submit(db, spec).sweep_id


def question(app: SlopeApp) -> str:
    return str(app.screen.query_one("#confirm-question").render())


async def listed(app: SlopeApp, pilot, sweep_id: int) -> SweepsScreen:
    """The sweeps screen once its table lists the sweep (and has it selected)."""
    await wait_until(pilot, lambda: isinstance(app.screen, SweepsScreen)
                     and app.screen.selected == sweep_id
                     and str(sweep_id) in app.screen.query_one("#sweep-table").rows)
    return app.screen


def test_cancel_asks_first_n_and_escape_keep_y_cancels(db):
    sweep = named(db, "[bold red]not markup", 4)

    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            screen = await listed(app, pilot, sweep)
            for keep in ("n", "escape", "enter"):  # enter: the focused button is Keep
                await pilot.press("c")
                await wait_until(pilot, lambda: isinstance(app.screen, ConfirmScreen))
                asked = question(app)
                assert f"Cancel sweep {sweep} '[bold red]not markup'?" in asked
                assert "Its 4 queued runs would be cancelled" in asked
                await pilot.press(keep)
                await wait_until(pilot, lambda: app.screen is screen)
                await pilot.pause(0.3)
                assert sweep_status(db, sweep) == "active", keep
                assert statuses(db, sweep) == {"queued": 4}, keep
            await pilot.press("c")
            await wait_until(pilot, lambda: isinstance(app.screen, ConfirmScreen))
            await pilot.press("y")
            await wait_until(pilot, lambda: sweep_status(db, sweep) == "cancelled")
            assert statuses(db, sweep) == {"cancelled": 4}

    run(scenario)


def test_resume_on_a_cancelled_sweep_queues_its_runs_again(db):
    from slopetui.sweeps import control

    sweep = submit_quick(db, 3).sweep_id
    control.cancel(db, sweep)

    async def scenario():
        app = app_for(db)
        said: list[str] = []
        notify = app.notify
        app.notify = lambda message, **kw: (said.append(message), notify(message, **kw))[1]
        async with app.run_test(size=(80, 24)) as pilot:
            await listed(app, pilot, sweep)
            await pilot.press("r")
            await wait_until(pilot, lambda: statuses(db, sweep) == {"queued": 3})
            await wait_until(pilot, lambda: bool(said))
        assert sweep_status(db, sweep) == "active"
        assert said == [f"sweep {sweep} resumed: 3 cancelled runs queued again"]

    run(scenario)


def test_delete_asks_then_deletes_and_the_list_forgets_the_sweep(db):
    kept = named(db, "kept", 2)
    doomed = named(db, "to delete", 3)

    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            screen = await listed(app, pilot, doomed)  # the newest is selected first
            await pilot.press("x")
            await wait_until(pilot, lambda: isinstance(app.screen, ConfirmScreen))
            assert f"Delete sweep {doomed} 'to delete' and its 3 runs?" in question(app)
            await pilot.press("n")
            await wait_until(pilot, lambda: app.screen is screen)
            await pilot.pause(0.3)
            assert sweep_status(db, doomed) == "active"
            await pilot.press("x")
            await wait_until(pilot, lambda: isinstance(app.screen, ConfirmScreen))
            await pilot.press("y")
            await wait_until(pilot, lambda: sweep_status(db, doomed) is None)
            table = screen.query_one("#sweep-table")
            await wait_until(pilot, lambda: list(table.rows) == [table.rows[str(kept)].key])
            assert screen.selected == kept  # the diagram of a sweep that exists
            await wait_until(pilot, lambda: screen._shown is not None
                             and screen._shown.id == kept)
        assert statuses(db, kept) == {"queued": 2} and statuses(db, doomed) == {}

    run(scenario)


def test_delete_is_refused_while_runs_are_running(db):

    sweep = submit_quick(db, 2).sweep_id
    claim_one(db, "w")

    async def scenario():
        app = app_for(db)
        said: list[str] = []
        notify = app.notify
        app.notify = lambda message, **kw: (said.append(message), notify(message, **kw))[1]
        async with app.run_test(size=(80, 24)) as pilot:
            screen = await listed(app, pilot, sweep)
            await pilot.press("x")
            await wait_until(pilot, lambda: bool(said))
            assert app.screen is screen  # not asked: it could not be done
            assert "1 running runs: cancel it (c)" in said[0]
        assert statuses(db, sweep) == {"running": 1, "queued": 1}

    run(scenario)


def test_the_queue_screen_asks_before_cancelling(db):
    sweep = submit_quick(db, 3).sweep_id

    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            await queue_with_rows(pilot, app, 1)
            queue = app.screen
            await pilot.press("c")
            await wait_until(pilot, lambda: isinstance(app.screen, ConfirmScreen))
            assert "Its 3 queued runs would be cancelled" in question(app)
            await pilot.press("n")
            await wait_until(pilot, lambda: app.screen is queue)
            await pilot.pause(0.3)
            assert statuses(db, sweep) == {"queued": 3}
            await pilot.press("c")
            await wait_until(pilot, lambda: isinstance(app.screen, ConfirmScreen))
            await pilot.press("y")
            await wait_until(pilot, lambda: statuses(db, sweep) == {"cancelled": 3})

    run(scenario)


def cells(bar: Text) -> dict[str, tuple[int, set[str]]]:
    """Per bar character: how many cells, and the styles they are drawn in."""
    out: dict[str, tuple[int, set[str]]] = {}
    for char, _ in BAR_CELLS:
        styles = {str(span.style) for span in bar.spans
                  if char in bar.plain[span.start:span.end]}
        out[char] = (bar.plain.count(char), styles)
    return out


def test_the_bar_of_a_sweep_whose_runs_all_failed_is_red_at_0_percent(db):
    failing = submit_quick(db, 4).sweep_id
    with db.transaction() as s:
        s.execute(update(Run).where(Run.sweep_id == failing).values(status="failed"))

    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            screen = await listed(app, pilot, failing)
            row = screen.query_one("#sweep-table").get_row(str(failing))
            bar = row[2]
            assert bar.plain == "▓" * BAR_WIDTH + "   0%"
            assert cells(bar)["▓"] == (BAR_WIDTH, {"red"})
            assert cells(bar)["█"][0] == 0  # no cell of it looks done
            assert str(row[3]) == "0/4"
            assert str(row[-1]) == "failed, 4 failed"

    run(scenario)


def test_the_bar_shows_done_failed_cancelled_and_left_apart():
    bar = progress_bar(done=5, total=10, failed=2, cancelled=1)
    assert bar.plain == "█████▓▓▒░░  50%"
    styles = cells(bar)
    assert styles["█"] == (5, {"green"}) and styles["▓"] == (2, {"red"})
    assert styles["▒"][0] == 1 and styles["░"][0] == 2
    # one failed run among a thousand still takes a cell: what went wrong stays visible
    few = progress_bar(done=999, total=1000, failed=1)
    assert few.plain.count("▓") == 1 and few.plain.endswith(" 99%")
    assert progress_bar(0, 0).plain == "░" * BAR_WIDTH + "   0%"


def test_the_name_column_takes_the_width_of_the_screen(db):
    sweep = named(db, LONG_NAME)

    async def name_cell(width: int) -> str:
        app = app_for(db)
        async with app.run_test(size=(width, 24)) as pilot:
            screen = await listed(app, pilot, sweep)
            table = screen.query_one("#sweep-table")
            name = str(table.get_row(str(sweep))[NAME_COLUMN])
            if len(name) > NAME_MIN:  # cut to the room left: the row fits, no scrolling
                assert table.virtual_size.width <= width
            return name

    async def scenario():
        assert await name_cell(140) == LONG_NAME
        cut = await name_cell(80)  # the other columns are narrow here: more than 20 left
        assert NAME_MIN < len(cut) < len(LONG_NAME) and cut == LONG_NAME[:len(cut) - 1] + "…"
        assert await name_cell(50) == LONG_NAME[:NAME_MIN - 1] + "…"  # never under NAME_MIN

    run(scenario)


def test_a_resize_widens_and_narrows_the_name_column(db):
    sweep = named(db, LONG_NAME)

    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(50, 24)) as pilot:
            screen = await listed(app, pilot, sweep)
            table = screen.query_one("#sweep-table")

            def name() -> str:
                return str(table.get_row(str(sweep))[NAME_COLUMN])

            assert len(name()) == NAME_MIN
            await pilot.resize_terminal(160, 24)
            await wait_until(pilot, lambda: name() == LONG_NAME)
            await pilot.resize_terminal(50, 24)
            await wait_until(pilot, lambda: len(name()) == NAME_MIN)
            name_column = list(table.columns.values())[NAME_COLUMN]
            assert name_column.get_render_width(table) == NAME_MIN + 2  # narrowed again

    run(scenario)


def own_footer_keys(app: SlopeApp, keys: set[str]) -> dict[str, int]:
    """The screen's own keys among the footer's, and the width each takes."""
    return {k.key: k.region.width for k in app.screen.query("FooterKey") if k.key in keys}


def footer_end(app: SlopeApp) -> int:
    """The column the footer's last key ends at (the app's keys and palette included)."""
    return max(k.region.right for k in app.screen.query("FooterKey"))


#: "About 45" columns for a screen's own keys: the app's (? Help, ^q Quit, ^p palette)
#: take the rest of 80.
OWN_KEYS_WIDTH = 47


def test_the_screens_own_footer_keys_fit_beside_the_apps_at_80_columns(db):
    submit_quick(db, 2)

    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            await wait_until(pilot, lambda: app.db is not None)
            await pilot.pause()
            shown = own_footer_keys(app, {"p", "r", "c", "f", "o", "d", "x"})
            assert set(shown) == {"p", "r", "c", "f", "o"}, shown  # d, x: help and palette
            assert sum(shown.values()) <= OWN_KEYS_WIDTH and footer_end(app) <= 80, shown
            await pilot.press("2")
            await wait_until(pilot, lambda: isinstance(app.screen, QueueScreen))
            await pilot.pause()
            shown = own_footer_keys(app, {"p", "r", "c"})
            assert set(shown) == {"p", "r", "c"}, shown
            assert sum(shown.values()) <= OWN_KEYS_WIDTH and footer_end(app) <= 80, shown

    run(scenario)


def test_the_queue_cursor_stays_on_its_sweep_when_another_is_submitted(db):
    older = submit_quick(db, 2).sweep_id
    submit_quick(db, 2, tau=3.0)

    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            table, _ = await queue_with_rows(pilot, app, 2)
            await pilot.press("down")  # the older sweep (newest first)
            await wait_until(pilot, lambda: table.cursor_row == 1)
            submit_quick(db, 2, tau=4.0)  # listed first: the older one moves to row 2
            await wait_until(pilot, lambda: table.row_count == 3)
            key = table.coordinate_to_cell_key(table.cursor_coordinate).row_key.value
            assert (table.cursor_row, key) == (2, str(older))

    run(scenario)
