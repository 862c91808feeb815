"""Pilot tests of the application: sweeps, the live diagram, the new-sweep form, the
queue screen, errors, and quitting without losing work."""

from __future__ import annotations

from sqlalchemy import func, select

from slopetui.store.database import Database
from slopetui.store.models import Run, Sweep, Worker
from slopetui.sweeps.spec import parse_spec
from slopetui.sweeps.submit import submit
from slopetui.tui.app import SlopeApp
from slopetui.tui.screens.confirm import ConfirmScreen
from slopetui.tui.screens.error import ErrorScreen
from slopetui.tui.screens.new_sweep import NewSweepScreen
from slopetui.tui.screens.queue import QueueScreen
from slopetui.tui.screens.run_detail import RunDetailScreen
from slopetui.tui.screens.sweeps import SweepsScreen
from slopetui.tui.widgets.bifurcation_view import BifurcationView
from slopetui.tui.widgets.phase_grid import FOOTER_ROWS, PhaseGrid
from tests.support import QUICK_SOLVER, finish_all
from tests.tui.support import fill, open_form, run, wait_until


def plane(db: Database, nx: int = 6, ny: int = 4) -> int:
    spec = parse_spec({"x": {"param": "k", "start": 2, "stop": 20, "num": nx},
                       "y": {"param": "tau", "start": 0.5, "stop": 10, "num": ny},
                       "solver": QUICK_SOLVER})
    return submit(db, spec).sweep_id


def app_for(db: Database) -> SlopeApp:
    return SlopeApp(db.display_url, start_workers=False, refresh_s=0.2)


def count(db: Database, *where) -> int:
    with db.sessions() as s:
        return s.scalar(select(func.count()).select_from(Run).where(*where))


def test_the_diagram_fills_as_results_land(db):
    sweep = plane(db)

    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            grid = app.query_one(PhaseGrid)
            await wait_until(pilot, lambda: grid.data is not None)
            assert {r for _, r in grid.data.runs.values()} == {None}  # all pending
            assert grid.data.hopf is not None and len(grid.data.hopf[0]) > 0
            finish_all(db)  # a worker elsewhere finishes the runs
            await wait_until(pilot, lambda: None not in {r for _, r in grid.data.runs.values()})
            regimes = {r for _, r in grid.data.runs.values()}
            assert "sliding" in regimes and "oscillatory" in regimes
            text = str(grid.render())
            assert "sliding (" in text and "Hopf (exact)" in text and "tau ↑" in text
            assert f"{sweep}" in str(app.query_one("#sweep-table").get_row_at(0)[0])

    run(scenario)


def test_the_cursor_opens_the_run_under_it(db):
    plane(db)
    finish_all(db)

    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            grid = app.query_one(PhaseGrid)
            await wait_until(pilot, lambda: grid.data is not None)
            await pilot.press("d", "right", "right", "up")
            run_id, k, tau, regime = grid.cursor_run()
            assert (k, tau) == (grid.data.xs[2], grid.data.ys[1])
            await pilot.press("enter")
            await wait_until(pilot, lambda: isinstance(app.screen, RunDetailScreen))
            assert app.screen.run_id == run_id
            with db.sessions() as s:
                run_row = s.get(Run, run_id)
                assert (run_row.k, run_row.tau, run_row.regime) == (k, tau, regime)

    run(scenario)


def test_failed_and_cancelled_runs_have_their_own_cells_in_the_grid(db):
    sweep = plane(db)
    finish_all(db)
    with db.sessions() as s:  # as a worker that gave up, and a cancelled run, leave them
        for (ix, iy), status in {(2, 1): "failed", (4, 2): "cancelled"}.items():
            run_row = s.scalars(select(Run).where(Run.sweep_id == sweep, Run.ix == ix,
                                                  Run.iy == iy)).one()
            run_row.status, run_row.regime = status, None
        s.commit()

    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            grid = app.query_one(PhaseGrid)
            await wait_until(pilot, lambda: grid.data is not None)
            # laid out: a display cell per run
            await wait_until(pilot, lambda: grid.size.height - FOOTER_ROWS >= len(grid.data.ys))
            assert grid.data.runs[(2, 1)][1] == "failed"
            assert grid.data.runs[(4, 2)][1] == "cancelled"
            assert None not in {r for _, r in grid.data.runs.values()}  # none pending
            text = grid.render()
            plain = str(text)
            assert "! failed (1)" in plain and "/ cancelled (1)" in plain
            assert "pending" not in plain
            # one cell each, besides the legend's marker: "!" in the foreground's colour
            assert plain.count("!") == 2 and plain.count("/") == 2
            colours = {str(span.style.color.name) for span in text.spans
                       if text.plain[span.start:span.end].strip() == "/"
                       and getattr(span.style, "color", None) is not None}
            assert colours == {"bright_black"}
            await pilot.press("d", "right", "right", "up")
            assert grid.cursor_run()[3] == "failed"
            assert ": failed (run " in str(grid.render())

    run(scenario)


def test_a_1d_sweep_shows_its_bifurcation_diagram(db):
    from tests.support import submit_quick
    submit_quick(db, 5)
    finish_all(db)

    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            view = app.query_one(BifurcationView)
            await wait_until(pilot, lambda: view.diagram is not None and "m_y peaks" in str(view.render()))
            await pilot.press("d", "right")
            assert "k = 6:" in str(view.render())  # the cursor's run is named in the title

    run(scenario)


def test_submitting_the_form_puts_the_runs_in_the_database(db):
    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            await open_form(app, pilot)
            fill(app, {"x-param": "k", "x-start": "3", "x-stop": "9", "x-num": "4",
                       "y-param": "tau", "y-start": "1", "y-stop": "4", "y-num": "3",
                       "fixed-delta": "1e-6", "solver-method": "rk4", "solver-dt": "0.01",
                       "solver-t_end": "500", "solver-window": "100", "name": "from the form"})
            await pilot.pause()
            assert "12 runs" in str(app.screen.query_one("#estimate").render())
            await pilot.press("ctrl+s")
            await wait_until(pilot, lambda: isinstance(app.screen, SweepsScreen))
        with db.sessions() as s:
            sweep = s.scalars(select(Sweep)).one()
            assert sweep.name == "from the form" and sweep.n_runs == 12
            assert {r.delta for r in s.scalars(select(Run))} == {1e-6}
        assert count(db, Run.status == "queued") == 12

    run(scenario)


def test_bad_form_input_shows_the_error_and_writes_nothing(db):
    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            form = await open_form(app, pilot)
            for values, expected, marked in (
                ({"x-num": "0"}, "x.num", "x-num"),
                ({"x-num": "5", "y-start": "-1"}, "y.tau", "y-start"),
                ({"y-start": "1", "fixed-a": "lots"}, "fixed.a: expected a number", "fixed-a"),
            ):
                fill(app, values)
                await pilot.pause()
                assert expected in str(form.query_one("#form-error").render())
                assert form.query_one(f"#{marked}").has_class("-invalid")
                await pilot.press("ctrl+s")
                await pilot.pause()
                assert isinstance(app.screen, NewSweepScreen)
        assert count(db) == 0
        with db.sessions() as s:
            assert s.scalar(select(func.count()).select_from(Sweep)) == 0

    run(scenario)


def test_friction_constraints_are_warnings_and_presets_fill_the_form(db):
    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            form = await open_form(app, pilot)
            fill(app, {"fixed-a": "0.03"})
            await pilot.pause()
            assert "⚠" in str(form.query_one("#form-warnings").render())
            assert str(form.query_one("#form-error").render()) == ""  # still submittable
            fill(app, {"preset": "fig7b"})
            await pilot.pause()
            assert form.query_one("#x-param").value == "a"
            assert form.query_one("#x-start").value == "0.03"
            assert form.query_one("#fixed-k").value == "12"
            assert "far from the fixed point" in str(form.query_one("#preset-note").render())

    run(scenario)


def test_queue_screen_shows_workers_and_pauses_a_sweep(db):
    sweep = plane(db, 2, 2)
    with db.transaction() as s:
        s.add(Worker(id="node7:4242", host="node7", pid=4242))

    async def scenario():
        app = app_for(db)
        said: list[str] = []
        notify = app.notify
        app.notify = lambda message, **kw: (said.append(message), notify(message, **kw))[1]
        async with app.run_test(size=(80, 24)) as pilot:
            await pilot.press("2")
            await wait_until(pilot, lambda: isinstance(app.screen, QueueScreen))
            workers = app.screen.query_one("#worker-table")
            await wait_until(pilot, lambda: workers.row_count == 1
                             and "node7:4242" in str(workers.get_row_at(0)[0]))
            await pilot.press("p")
            await wait_until(pilot, lambda: _sweep_status(db, sweep) == "paused")
            await pilot.press("r")
            await wait_until(pilot, lambda: _sweep_status(db, sweep) == "active")
            await pilot.press("c")  # asks first (screens.confirm): y cancels
            await wait_until(pilot, lambda: isinstance(app.screen, ConfirmScreen))
            await pilot.press("y")
            await wait_until(pilot, lambda: _sweep_status(db, sweep) == "cancelled")
            # the lines `slopetui pause|resume|cancel` prints (sweeps.control.apply)
            await wait_until(pilot, lambda: len(said) == 3)
        assert said == [f"sweep {sweep} is paused", f"sweep {sweep} is active",
                        f"sweep {sweep} cancelled: 4 queued runs cancelled"]
        assert count(db, Run.status == "cancelled") == 4

    run(scenario)


def _sweep_status(db: Database, sweep_id: int) -> str:
    with db.sessions() as s:
        return s.get(Sweep, sweep_id).status


def test_a_database_that_cannot_be_opened_is_shown_not_raised(tmp_path):
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder")

    async def scenario():
        app = SlopeApp(f"sqlite:///{blocker}/store.db", start_workers=False)
        async with app.run_test(size=(80, 24)) as pilot:
            await wait_until(pilot, lambda: isinstance(app.screen, ErrorScreen)
                             and bool(app.screen.query("#error-cause")))
            assert "cannot be opened" in str(app.screen.query_one("#error-title").render())
            assert "a-file" in str(app.screen.query_one("#error-cause").render())

    run(scenario)


def test_quitting_keeps_queued_work(db):
    plane(db, 3, 2)

    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            await wait_until(pilot, lambda: app.query_one(PhaseGrid).data is not None)
            await pilot.press("q")
    run(scenario)
    assert count(db, Run.status == "queued") == 6


def test_no_color_keeps_the_regimes_apart_by_marker(db, monkeypatch):
    from tests.support import submit_quick
    submit_quick(db, 5)
    finish_all(db)
    monkeypatch.setenv("NO_COLOR", "1")

    async def scenario():
        app = app_for(db)
        assert app.no_color
        async with app.run_test(size=(80, 24)) as pilot:
            view = app.query_one(BifurcationView)
            await wait_until(pilot, lambda: view.diagram is not None and "m_y peaks" in str(view.render()))
            text = view.render()
            assert not text.spans  # plain text: no colour at all
            assert ". sliding (" in str(text) and "o oscillatory (" in str(text)

    run(scenario)


def test_the_form_takes_a_history_and_a_list_of_deltas(db):
    """Two deltas make every point twice (the map of where they differ); a bad delta in
    the list is marked and writes nothing; the history goes on every run."""
    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            form = await open_form(app, pilot)
            fill(app, {"x-param": "k", "x-start": "3", "x-stop": "9", "x-num": "4",
                       "y-param": "tau", "y-start": "1", "y-stop": "4", "y-num": "3",
                       "solver-method": "rk4", "solver-dt": "0.01", "solver-t_end": "500",
                       "solver-window": "100", "initial-deltas": "1e-6, x"})
            await pilot.pause()
            assert "initial[1].delta" in str(form.query_one("#form-error").render())
            assert form.query_one("#initial-deltas").has_class("-invalid")
            fill(app, {"initial-deltas": "1e-6, 0.1", "solver-history": "consistent"})
            await pilot.pause()
            assert "24 runs" in str(form.query_one("#estimate").render())
            await pilot.press("ctrl+s")
            await wait_until(pilot, lambda: isinstance(app.screen, SweepsScreen))
        with db.sessions() as s:
            runs = list(s.scalars(select(Run)))
        assert sorted({(r.ic, r.delta) for r in runs}) == [(0, 1e-6), (1, 0.1)]
        assert {r.history for r in runs} == {"consistent"} and len(runs) == 24

    run(scenario)


def test_a_background_action_ends_in_done_or_failed_and_a_replaced_one_in_neither(db):
    """The app's one pattern for what takes time (slopetui.tui.background): the action's
    return value reaches done, its exception failed (the application runs on), and an
    action of an exclusive group replaced by a newer one reaches neither."""
    import threading

    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            ended: list[object] = []
            release = threading.Event()

            def slow() -> str:
                release.wait(10)
                return "replaced"

            def fail() -> str:
                raise OSError("disk full")

            app.background.start(slow, done=ended.append, failed=ended.append, group="t",
                                 exclusive=True)
            app.background.start(lambda: "newer", done=ended.append, failed=ended.append,
                                 group="t", exclusive=True)
            app.background.start(fail, done=ended.append, failed=ended.append, group="u")
            await wait_until(pilot, lambda: len(ended) == 2)
            release.set()
            await app.workers.wait_for_complete()
            await pilot.pause(0.2)
            assert "newer" in ended and "replaced" not in ended and len(ended) == 2
            failure = next(e for e in ended if e != "newer")
            assert isinstance(failure, OSError) and str(failure) == "disk full"
            assert app.is_running

    run(scenario)
