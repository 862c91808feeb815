"""The run detail screen (Pilot, 80x24) and its plot renderers (slopetui.plots.run_plots).

No pytest-asyncio here: each Pilot test is a sync test that runs its scenario with
asyncio.run.
"""

from __future__ import annotations

import asyncio
import re
from collections.abc import Awaitable, Callable

import numpy as np
import pytest
from sqlalchemy import select, update
from textual.pilot import Pilot
from textual.widgets import Static, TabbedContent

from slopetui.plots.run_plots import (
    MX_LABEL,
    detrend,
    envelope,
    render_lyapunov,
    render_phase_portrait,
    render_spectrum,
    render_time_series,
)
from slopetui.queue import jobs
from slopetui.store.database import Database
from slopetui.store.models import Run
from slopetui.store.open import open_store
from slopetui.tui.app import SlopeApp
from slopetui.tui.screens.run_detail import (
    MATCH_TEXT,
    RECOMPUTED_NOTE,
    TAB_CERT,
    TAB_LYAP,
    TAB_PHASE,
    TAB_ROOTS,
    TAB_SPECTRUM,
    TAB_TIME,
    RunDetailScreen,
)
from slopetui.tui.widgets.plot_view import PlotView
from tests.support import claim_one, finish_all, submit_quick
from tests.tui.support import wait_until

ANSI = re.compile(r"\x1b\[")
SIZE = (80, 24)
#: Seconds a scenario may wait for the screen's workers (a cold numba cache compiles first).
SETTLE_S = 120.0

Scenario = Callable[[SlopeApp, Pilot], Awaitable[None]]


# -- helpers ---------------------------------------------------------------------------------

def run_ids(db: Database) -> list[int]:
    with db.sessions() as s:
        return list(s.scalars(select(Run.id).order_by(Run.id)))


def play(db_url: str, scenario: Scenario) -> None:
    """Run the app on the store at db_url (no worker pool) and play scenario in it."""
    async def main() -> None:
        app = SlopeApp(db_url, start_workers=False)
        async with app.run_test(size=SIZE) as pilot:
            await wait_until(pilot, lambda: app.db is not None, SETTLE_S)
            await scenario(app, pilot)
    asyncio.run(main())


def text_of(screen: RunDetailScreen, selector: str) -> str:
    return str(screen.query_one(selector, Static).content)


def status(screen: RunDetailScreen) -> str:
    return text_of(screen, "#run-status")


def settled(screen: RunDetailScreen) -> Callable[[], bool]:
    """The screen has finished loading and (if it recomputes) recomputing."""
    def check() -> bool:
        text = status(screen)
        return bool(text) and not text.startswith(("loading", "recomputing", "waiting"))
    return check


async def open_run(app: SlopeApp, pilot: Pilot, run_id: int) -> RunDetailScreen:
    app.open_run(run_id)
    await pilot.pause()
    screen = app.screen
    assert isinstance(screen, RunDetailScreen)
    await wait_until(pilot, settled(screen), SETTLE_S)
    return screen


# -- the screen ------------------------------------------------------------------------------

@pytest.fixture
def done_store(db_url: str) -> list[int]:
    """Two finished runs (k = 4: sliding at rest; k = 12: oscillating), RK4 to t_end = 600."""
    db = open_store(db_url)
    submit_quick(db, 2, t_end=600.0)
    finish_all(db)
    ids = run_ids(db)
    db.dispose()
    return ids


def test_a_done_run_shows_its_summary_four_plots_and_the_match(db_url, done_store):
    db = open_store(db_url)
    with db.sessions() as s:
        stored = s.get(Run, done_store[-1])
        regime, k = stored.regime, stored.k
        stored_multipliers = stored.multipliers
    db.dispose()

    async def scenario(app: SlopeApp, pilot: Pilot) -> None:
        screen = await open_run(app, pilot, done_store[-1])
        summary = text_of(screen, "#run-summary")
        assert f"run {done_store[-1]}" in summary and regime in summary
        assert f"k {k:g}" in summary and "rk4" in summary and "λmax" in summary
        assert RECOMPUTED_NOTE in str(screen.sub_title)  # in the header, beside the run's id
        assert status(screen).startswith(MATCH_TEXT)
        tabs = screen.query_one("#run-tabs", TabbedContent)
        assert tabs.tab_count == 6
        for key, tab in zip("tpsl", (TAB_TIME, TAB_PHASE, TAB_SPECTRUM, TAB_LYAP), strict=True):
            await pilot.press(key)
            await pilot.pause()
            await pilot.pause()
            assert tabs.active == tab
            plot = screen.query_one(f"#{tab} PlotView", PlotView)
            drawn = str(plot.content)
            assert plot.size.height >= 12, "the plot must keep its room at 80x24"
            assert "┌" in drawn and "too small" not in drawn, f"{tab}: {drawn[:200]}"
        # the certificate in full, and a certified orbit's multipliers against the circle
        await pilot.press("c")
        await pilot.pause()
        assert tabs.active == TAB_CERT
        shown = text_of(screen, "#certificate-text")
        assert shown.startswith(("certified: ", "not certified: "))
        assert ("inside the unit circle" in shown) == bool(stored_multipliers)
        # and drawn: the circle with each multiplier on it or off it
        circle = screen.query_one("#plot-multipliers", PlotView)
        assert stored_multipliers, "k = 12 settles on a certified orbit"
        assert circle.display and "|μ| = 1" in str(circle.content)
        assert f"{len(stored_multipliers)} inside" in str(circle.content)
        await pilot.press("escape")
        await pilot.pause()
        assert not isinstance(app.screen, RunDetailScreen)

    play(db_url, scenario)


def test_a_long_summary_scrolls_the_screen_packed_to_the_room_the_scrollbar_leaves(
        db_url, done_store):
    """A certified cycle with a long regime detail and flags takes more lines than the
    plot leaves at 80 x 24, so the screen scrolls (the plot keeps the 12 lines it needs);
    the scrollbar then takes two columns, and the summary, packed to the full width, was
    wrapped again two columns short, an item cut across two lines ("peaks 1 / (1.99)").
    Packed again to the narrower width, every line fits."""
    db = open_store(db_url)
    with db.sessions() as s, s.begin():
        s.execute(update(Run).where(Run.id == done_store[-1]).values(
            detail="period-1, 1 maximum, 0.99 T_H (certified); unrealisable from t = 0.001 "
                   "(min s_x -3.64e-05, s_y -0.000944, s_x s_y - u^2 -0.000125)",
            flags="uphill,unrealisable"))
    db.dispose()

    async def scenario(app: SlopeApp, pilot: Pilot) -> None:
        screen = await open_run(app, pilot, done_store[-1])
        await pilot.pause()
        await pilot.pause()
        summary = screen.query_one("#run-summary", Static)
        assert screen.max_scroll_y > 0, "the long detail scrolls the screen: the case at stake"
        room = summary.content_size.width
        assert room == SIZE[0] - 2 - 2  # the padding and the scrollbar
        lines = str(summary.content).splitlines()
        # a line of several items fits; only an item longer than a line (the long regime
        # detail) goes on, wrapped by the screen
        assert all(len(line) <= room for line in lines if " · " in line)
        assert any(line.startswith("peaks 1 (") for line in lines)  # not cut from its value

    play(db_url, scenario)


def test_a_fixed_point_says_so_in_the_phase_portrait(db_url, done_store):
    async def scenario(app: SlopeApp, pilot: Pilot) -> None:
        screen = await open_run(app, pilot, done_store[0])  # k = 4: sliding at rest
        assert "sliding" in text_of(screen, "#run-summary")
        assert status(screen).startswith(MATCH_TEXT)
        await pilot.press("p")
        await pilot.pause()
        assert "fixed point" in str(screen.query_one(f"#{TAB_PHASE} PlotView", PlotView).content)

    play(db_url, scenario)


def test_the_roots_tab_lists_and_draws_the_rest_states_roots(db_url, done_store):
    """Computed when the tab is first shown, in a worker; checked against what does not
    come from the roots: the run at rest decays at the rate its simulation measured (its
    stored lambda_max), and the run at k = 12 lies past the exact Hopf curve k_H(tau = 2)
    = 9.13 (core.stability's closed form), where the rest state is unstable."""
    db = open_store(db_url)
    with db.sessions() as s:
        resting = s.get(Run, done_store[0])
        measured, error = resting.lambda_max, resting.lambda_err
    db.dispose()

    async def scenario(app: SlopeApp, pilot: Pilot) -> None:
        for run_id, said, sign in ((done_store[0], "stable", "Re λ1 < 0"),
                                   (done_store[-1], "unstable", "Re λ1 > 0")):
            screen = await open_run(app, pilot, run_id)
            assert screen.roots is None  # not computed before it is looked at
            await pilot.press("e")
            await wait_until(pilot, lambda s=screen: s.roots is not None, SETTLE_S)
            await pilot.pause()
            tabs = screen.query_one("#run-tabs", TabbedContent)
            assert tabs.active == TAB_ROOTS and screen.roots is not None
            found = screen.roots
            listed = text_of(screen, "#roots-text").splitlines()
            assert listed[:3] == [f"sliding state: {said}", "by its leading nonzero root:",
                                  sign]
            assert listed[3].startswith("o λ1 ") and listed[3].endswith("  leading")
            assert len(listed) == 3 + len(found.roots)  # one line a root, pairs once
            assert {line[0] for line in listed[3:]} == {"o", "x"}  # the plot's markers
            plot = screen.query_one("#plot-roots", PlotView)
            drawn = str(plot.content)
            assert "┌" in drawn and "Re = 0" in drawn and "too small" not in drawn
            assert plot.size.height >= 12
            if said == "stable":
                assert abs(found.roots[0].value.real - measured) < 2 * error
            await pilot.press("escape")
            await pilot.pause()

    play(db_url, scenario)


def test_roots_that_cannot_be_computed_say_why_on_the_tab(db_url, done_store):
    """At tau = 200, k = 3 (d = 1e-4) the variance block's real root -3.456 is not carried
    to the noisy rest state (core.rest_stability.rest_roots raises): said, not raised."""
    db = open_store(db_url)
    with db.transaction() as s:  # queued: nothing is recomputed, the roots still are
        s.execute(update(Run).where(Run.id == done_store[0])
                  .values(tau=200.0, k=3.0, status="queued"))
    db.dispose()

    async def scenario(app: SlopeApp, pilot: Pilot) -> None:
        screen = await open_run(app, pilot, done_store[0])
        await pilot.press("e")
        await wait_until(pilot, lambda: "cannot be computed" in text_of(screen, "#roots-text"),
                         SETTLE_S)
        said = text_of(screen, "#roots-text")
        assert "ArithmeticError: the root -3.456" in said and screen.roots is None
        assert "┌" not in str(screen.query_one("#plot-roots", PlotView).content)

    play(db_url, scenario)


def test_a_result_that_differs_from_the_stored_one_is_a_warning(db_url, done_store):
    db = open_store(db_url)
    with db.transaction() as s:
        s.execute(update(Run).where(Run.id == done_store[-1])
                  .values(regime="mixed", lambda_max=0.5, lambda_err=0.001, engine="0123456789abcdef"))
    db.dispose()

    async def scenario(app: SlopeApp, pilot: Pilot) -> None:
        screen = await open_run(app, pilot, done_store[-1])
        text = status(screen)
        assert text.startswith("warning") and "stored mixed" in text
        assert "engine changed" in text and "0123456789abcdef" in text
        assert screen.query_one("#run-status").has_class("warning")

    play(db_url, scenario)


def test_a_missing_run_is_an_error_on_screen_not_a_crash(db_url, done_store):
    async def scenario(app: SlopeApp, pilot: Pilot) -> None:
        screen = await open_run(app, pilot, 9999)
        assert "there is no run 9999" in status(screen)
        assert screen.query_one("#run-status").has_class("error")
        await pilot.press("r")  # nothing loaded: a notice, no crash
        await pilot.pause()
        await pilot.press("escape")
        await pilot.pause()
        assert not isinstance(app.screen, RunDetailScreen)

    play(db_url, scenario)


def test_a_recomputation_that_raises_shows_its_cause(db_url, done_store):
    db = open_store(db_url)
    with db.transaction() as s:  # dt > tau: the solver refuses the grid (in the worker)
        s.execute(update(Run).where(Run.id == done_store[0]).values(dt=5.0))
    db.dispose()

    async def scenario(app: SlopeApp, pilot: Pilot) -> None:
        screen = await open_run(app, pilot, done_store[0])
        text = status(screen)
        assert text.startswith("recomputation failed: ParameterError: dt = 5.0")
        assert "Traceback" not in text
        assert not screen.query_one("#run-tabs").loading

    play(db_url, scenario)


def test_a_failed_run_shows_its_error_and_computes_only_on_request(db_url):
    db = open_store(db_url)
    submit_quick(db, 1)
    job = claim_one(db, "w")
    traceback = "Traceback (most recent call last):\n  File \"x.py\", line 1\nRuntimeError: boom"
    assert jobs.fail(db, job, "w", traceback, max_attempts=1) == "failed"
    db.dispose()

    async def scenario(app: SlopeApp, pilot: Pilot) -> None:
        screen = await open_run(app, pilot, job.run_id)
        summary = text_of(screen, "#run-summary")
        assert "failed" in summary and "RuntimeError: boom" in summary
        assert "Traceback" not in summary
        assert "press r" in status(screen)
        assert str(screen.query_one(f"#{TAB_TIME} PlotView", PlotView).content) == ""
        await pilot.press("r")
        await pilot.pause()
        await wait_until(pilot, settled(screen), SETTLE_S)
        assert status(screen).startswith("computed:")
        assert "┌" in str(screen.query_one(f"#{TAB_TIME} PlotView", PlotView).content)

    play(db_url, scenario)


# -- the renderers ---------------------------------------------------------------------------

def drifting_cycle(n: int = 20001) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A limit cycle sliding at 0.1 per time unit: m_x = 0.1 t - cos t, m_y = dm_x/dt."""
    t = np.linspace(0.0, 200.0, n)
    return t, 0.1 * t - np.cos(t), 0.1 + np.sin(t)


def check_block(text: str, width: int, height: int, color: bool) -> None:
    lines = text.split("\n")
    assert len(lines) == height
    if not color:
        assert not ANSI.search(text)
        assert max(len(line) for line in lines) <= width


@pytest.mark.parametrize("color", [False, True])
@pytest.mark.parametrize("size", [(80, 16), (40, 13), (120, 30)])
def test_renderers_fill_exactly_their_size(color, size):
    width, height = size
    t, m_x, m_y = drifting_cycle()
    freq = np.fft.rfftfreq(len(t), t[1] - t[0])
    power = np.abs(np.fft.rfft(m_y - m_y.mean())) ** 2
    lam_t = np.linspace(1.0, 200.0, 1000)
    lam = 1.0 / lam_t
    for text in (render_time_series(t, m_x, m_y, width=width, height=height, color=color),
                 render_phase_portrait(t, m_x, m_y, width=width, height=height, color=color),
                 render_spectrum(freq, power, width=width, height=height, color=color),
                 render_lyapunov(lam_t, lam, estimate="0.0008(9)", width=width, height=height,
                                 color=color)):
        check_block(text, width, height, color)
        if color:
            assert ANSI.search(text)


def test_the_drift_of_m_x_is_removed_and_labelled():
    t, m_x, m_y = drifting_cycle()
    residual, slope = detrend(t, m_x)
    assert slope == pytest.approx(0.1, rel=1e-2)  # the window is not a whole number of periods
    assert np.ptp(residual) < 2.1  # the cycle's own swing (2), not the ramp (20)
    text = render_phase_portrait(t, m_x, m_y, width=80, height=16, color=False)
    assert MX_LABEL in text and "slope 0.1" in text


def test_envelope_keeps_the_extremes_and_bounds_the_points():
    t, _, m_y = drifting_cycle(100001)
    xs, ys = envelope(t, m_y, 400)
    assert len(xs) <= 400 and np.all(np.diff(xs) > 0)
    assert ys.max() == m_y.max() and ys.min() == m_y.min()
    xs, ys = envelope(t[1:], m_y[1:], 400, log=True)
    assert len(xs) <= 400 and np.all(np.diff(xs) > 0)


def test_nothing_to_plot_is_a_message_of_the_full_size():
    empty = np.zeros(0)
    for text in (render_time_series(empty, empty, empty, width=60, height=14, color=False),
                 render_phase_portrait(empty, empty, empty, width=60, height=14, color=False),
                 render_spectrum(empty, empty, width=60, height=14, color=False),
                 render_lyapunov(empty, empty, width=60, height=14, color=False)):
        check_block(text, 60, 14, False)
        assert text.strip()


def test_the_lyapunov_plot_has_a_zero_line_and_the_estimate():
    t = np.linspace(1.0, 1000.0, 500)
    text = render_lyapunov(t, -0.2 + 1.0 / t, estimate="-0.2000(1)", width=80, height=16,
                           color=False)
    assert "λmax = -0.2000(1)" in text
    assert "----" in text  # the dashed zero line


def test_unequal_lengths_are_refused():
    with pytest.raises(ValueError, match="differ in length"):
        render_time_series(np.arange(3.0), np.arange(4.0), np.arange(3.0), width=80, height=16,
                           color=False)
