"""What the cockpit shows in its states (Pilot, 80x24): the new-sweep form as it opens
(focus, the axis headings, its buttons within a scroll), the λmax toggle and the swept
parameters without colour, the cursor of the 1-D bifurcation view, the run detail's
time series zoom, and footers that fit 80 columns.

No pytest-asyncio: each scenario runs with asyncio.run (tests/tui/support.py).
"""

from __future__ import annotations

import re

import numpy as np
import pytest
from textual.pilot import Pilot
from textual.widgets import Input

from slopetui.plots.bifurcation import CURSOR_MARKER, render_bifurcation
from slopetui.plots.run_plots import render_time_series
from slopetui.store.database import Database
from slopetui.store.open import open_store
from slopetui.tui.app import SlopeApp
from slopetui.tui.screens.compare import CompareScreen
from slopetui.tui.screens.new_sweep import SWEPT, NewSweepScreen
from slopetui.tui.screens.run_detail import TAB_TIME, RunDetailScreen
from slopetui.tui.widgets.bifurcation_view import BifurcationView
from slopetui.tui.widgets.plot_view import PlotView
from tests.support import finish_all, submit_quick
from tests.tui.support import open_form, run, wait_until
from tests.tui.test_tui_app import app_for
from tests.tui.test_tui_run_detail import open_run, play, run_ids

#: The markers of the regimes (slopetui.plots.regime_colors): what a run's peaks look like.
REGIME_MARKERS = set(".o*+x")
NUMBER = re.compile(r"-?\d+(?:\.\d+)?(?:e[-+]?\d+)?")


# -- the new-sweep form -----------------------------------------------------------------------

def test_the_form_opens_on_the_name_under_headings_and_scrolls_to_its_buttons(db):
    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            form = await open_form(app, pilot)
            await pilot.pause()
            assert app.focused is form.query_one("#name", Input)  # typing goes into the form
            scroll = form.query_one("#form")
            heading = form.query_one("#axis-heading")
            assert scroll.region.contains_region(heading.region)  # on screen as the form opens
            labels = {str(label.render()): label.region.x for label in heading.query("Label")}
            for text, column in (("start", "x-start"), ("stop", "x-stop"), ("points", "x-num"),
                                 ("spacing", "x-spacing")):
                assert labels[text] == form.query_one(f"#{column}").region.x, text  # aligned
            # the form is taller than 80x24 holds: the buttons are reached by scrolling
            scroll.scroll_end(animate=False)
            await pilot.pause()
            for button in ("#submit", "#cancel"):
                assert scroll.region.contains_region(form.query_one(button).region), button

    run(scenario)


def test_the_lambda_toggle_reads_on_and_off_without_colour(db, monkeypatch):
    monkeypatch.setenv("NO_COLOR", "1")

    async def scenario():
        app = app_for(db)
        assert app.no_color
        async with app.run_test(size=(80, 24)) as pilot:
            form = await open_form(app, pilot)
            box = form.query_one("#solver-lyap")
            on = str(box.render())
            box.focus()
            await pilot.press("space")
            await pilot.pause()
            off = str(box.render())
            assert form.form_data()["solver"]["lyap"] is False
            assert on != off, "on and off must differ in their characters, not their colour"
            assert "✓" in on and "✓" not in off and "λmax" in off

    run(scenario)


def shown(box: Input) -> str:
    """The text an input shows (its value, or its placeholder when empty)."""
    return box.render_line(0).text.strip()


def test_a_swept_parameter_shows_swept_and_gets_its_value_back(db):
    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            form = await open_form(app, pilot)
            await pilot.pause()
            k, a = form.query_one("#fixed-k", Input), form.query_one("#fixed-a", Input)
            assert k.disabled and shown(k) == SWEPT  # k is the default x axis
            assert not a.disabled and shown(a) == "3.2"
            form.query_one("#x-param").value = "a"
            await pilot.pause()
            await pilot.pause()
            assert not k.disabled and shown(k) == "10"
            assert a.disabled and shown(a) == SWEPT
            k.value = "12"  # a value of one's own survives being swept
            form.query_one("#x-param").value = "k"
            await pilot.pause()
            await pilot.pause()
            assert k.disabled and shown(k) == SWEPT
            assert not a.disabled and shown(a) == "3.2"
            assert "k" not in form.form_data()["fixed"]
            form.query_one("#x-param").value = "v"
            await pilot.pause()
            await pilot.pause()
            assert shown(k) == "12" and form.form_data()["fixed"]["k"] == "12"

    run(scenario)


# -- the bifurcation view's cursor ----------------------------------------------------------

def cursor_column(text: str) -> int:
    """The one column of the plot holding the cursor's line; asserts it holds one of the
    chosen run's markers too (its peaks are drawn on the line)."""
    lines = text.split("\n")
    columns = {i for line in lines for i, ch in enumerate(line) if ch == CURSOR_MARKER}
    assert len(columns) == 1, f"one cursor column expected: {sorted(columns)}\n{text}"
    (column,) = columns
    assert {line[column] for line in lines if len(line) > column} & REGIME_MARKERS, text
    return column


def test_the_bifurcation_view_draws_its_cursor_and_moves_it(db, monkeypatch):
    submit_quick(db, 5)  # k = 4, 6, 8, 10, 12
    finish_all(db)
    monkeypatch.setenv("NO_COLOR", "1")  # the line must show without colour

    async def scenario():
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            view = app.query_one(BifurcationView)
            await wait_until(pilot, lambda: view.diagram is not None
                             and "m_y peaks" in str(view.render()))
            rendered = view.render()
            assert not rendered.spans
            frame = str(rendered).split("\n")
            left = min(line.index("┌") for line in frame if "┌" in line)
            right = max(line.index("┐") for line in frame if "┐" in line)
            columns = [cursor_column(str(rendered))]
            await pilot.press("d")
            for value in (6, 8, 10, 12):
                await pilot.press("right")
                await pilot.pause()
                text = str(view.render())
                assert f"k = {value}:" in text
                columns.append(cursor_column(text))
            assert columns == sorted(set(columns)), columns  # it moves right, step by step
            # the ends of the sweep are the ends of the axis (pinned to the sweep's range)
            assert columns[0] == left + 1 and columns[-1] == right - 1, (columns, left, right)

    run(scenario)


def test_the_cursor_shows_over_peaks_at_one_value_and_only_where_the_axis_can_show_it():
    # every run at rest at one m_y: the line still spans rows, not one cell under a marker
    flat = render_bifurcation("k", [1.0, 2.0, 3.0], [[0.0], [0.0], [0.0]], ["sliding"] * 3,
                              width=60, height=14, color=False, cursor=2.0)
    assert sum(CURSOR_MARKER in line for line in flat.split("\n")) > 3, flat
    assert CURSOR_MARKER not in render_bifurcation("k", [1.0, 2.0], [[1.0], [2.0]],
                                                   ["oscillatory"] * 2, color=False)
    on_log = render_bifurcation("tau", [0.0, 1.0, 10.0], [[1.0], [1.0], [2.0]],
                                ["oscillatory"] * 3, log=True, color=False, cursor=0.0)
    assert CURSOR_MARKER not in on_log  # no place for 0 on a log axis


# -- the run detail's time series ----------------------------------------------------------

@pytest.fixture
def long_window_store(db_url: str) -> list[int]:
    """k = 4 (sliding at rest) and k = 12 (oscillating, period ~2.5): a 400-unit window of
    ~160 periods, so 10, 50 and all of them are three different spans."""
    db: Database = open_store(db_url)
    submit_quick(db, 2, t_end=600.0, window=400.0)
    finish_all(db)
    ids = run_ids(db)
    db.dispose()
    return ids


def time_plot(screen: RunDetailScreen) -> str:
    return str(screen.query_one(f"#{TAB_TIME} PlotView", PlotView).content)


def tick_span(text: str) -> float:
    """The range of the x axis: the frame's bottom line holds a tick mark (┬) under each
    number of the line below it, at round values inside the range (slopetui.plots.ticks);
    the values against the marks' columns give the scale, which the plot's width (the
    columns between └ and ┘, the first at the range's start, the last at its end) turns
    into the range."""
    lines = text.split("\n")
    at = next(i for i, line in enumerate(lines) if "└" in line)
    frame, labels = lines[at], lines[at + 1]
    marks = [col for col, ch in enumerate(frame) if ch == "┬"]
    values = [float(v) for v in NUMBER.findall(labels)]
    assert len(values) >= 2 and len(values) == len(marks), (frame, labels)
    per_column = (values[-1] - values[0]) / (marks[-1] - marks[0])
    return per_column * (frame.index("┘") - frame.index("└") - 2)


def test_the_time_series_shows_the_last_periods_and_zooms_out(db_url, long_window_store):
    async def scenario(app: SlopeApp, pilot: Pilot) -> None:
        screen = await open_run(app, pilot, long_window_store[-1])  # oscillating
        await wait_until(pilot, lambda: "┌" in time_plot(screen))
        spans = []
        for label in ("the last 10 periods", "the last 50 periods", "the whole window"):
            text = time_plot(screen)
            assert f"t ({label})" in text, text
            spans.append(tick_span(text))
            await pilot.press("z")
            await pilot.pause()
        assert spans[0] < 30 < spans[1] < 130 < spans[2], spans  # ~25, ~125, ~400 time units
        assert "t (the last 10 periods)" in time_plot(screen)  # z came round
        await pilot.press("p", "z")  # z brings the time series back into view
        await pilot.pause()
        assert screen.query_one("#run-tabs").active == TAB_TIME
        assert "t (the last 50 periods)" in time_plot(screen)

    play(db_url, scenario)


def test_a_fixed_point_shows_its_whole_window(db_url, long_window_store):
    async def scenario(app: SlopeApp, pilot: Pilot) -> None:
        screen = await open_run(app, pilot, long_window_store[0])  # k = 4: at rest
        await wait_until(pilot, lambda: "┌" in time_plot(screen))
        text = time_plot(screen)
        assert "t (the whole window)" in text and tick_span(text) > 350, text

    play(db_url, scenario)


def test_the_time_series_renderer_cuts_the_window_at_n_periods():
    t = np.linspace(0.0, 400.0, 40001)
    m_x = 0.1 * t - np.cos(2 * np.pi * t / 2.5)
    m_y = np.gradient(m_x, t)
    spans = {}
    for periods in (10, 50, None):
        text = render_time_series(t, m_x, m_y, frequency=0.4, periods=periods, width=80,
                                  height=16, color=False)
        assert len(text.split("\n")) == 16
        spans[periods] = tick_span(text)
    # a tick mark sits on the column nearest its value: a column of the 73 is 1.4 %
    assert spans[10] == pytest.approx(25, rel=0.03) and spans[50] == pytest.approx(125, rel=0.03)
    assert spans[None] == pytest.approx(400, rel=0.03)
    # no frequency: nothing to count periods in, the whole window
    assert "t (the whole window)" in render_time_series(t, m_x, m_y, periods=10, width=80,
                                                         height=16, color=False)


# -- footers at 80 columns ------------------------------------------------------------------

def footer_keys(app: SlopeApp) -> dict[str, int]:
    """The footer's keys on show and the column each ends at."""
    return {key.key: key.region.right for key in app.screen.query("FooterKey")}


def test_the_footers_show_their_screens_own_keys_within_80_columns(db_url, long_window_store):
    async def scenario(app: SlopeApp, pilot: Pilot) -> None:
        await open_run(app, pilot, long_window_store[-1])
        await pilot.pause()
        keys = footer_keys(app)
        assert {"escape", "r", "z", "f", "m"} <= set(keys), keys
        assert not {"t", "p", "s", "l"} & set(keys), keys  # the tabs are on screen
        assert max(keys.values()) <= 80, keys
        app.push_screen(CompareScreen(long_window_store))
        await wait_until(pilot, lambda: isinstance(app.screen, CompareScreen))
        await pilot.pause()
        keys = footer_keys(app)
        assert {"escape", "f"} <= set(keys) and not {"t", "p"} & set(keys), keys
        assert max(keys.values()) <= 80, keys
        app.push_screen(NewSweepScreen())
        await wait_until(pilot, lambda: isinstance(app.screen, NewSweepScreen))
        await pilot.pause()
        keys = footer_keys(app)
        assert {"ctrl+s", "escape"} <= set(keys) and max(keys.values()) <= 80, keys

    play(db_url, scenario)
