"""Where the application writes its figures (f): $SLOPETUI_FIGURES or the user data
folder's figures/, created when missing, never the folder it was started in; the
notice names the whole path (Pilot, 80x24)."""

from __future__ import annotations

from pathlib import Path

import pytest

from slopetui.store.database import Database
from slopetui.tui.figure_writing import FIGURES_ENV
from tests.support import finish_all, submit_quick
from tests.tui.support import run, wait_until
from tests.tui.test_tui_app import app_for

#: A cold numba cache compiles the kernels first.
SETTLE_S = 120.0


def test_the_figure_key_writes_into_the_configured_folder_and_names_it(
        db: Database, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    started_in, folder = tmp_path / "checkout", tmp_path / "data" / "figures"  # not there yet
    started_in.mkdir()
    monkeypatch.chdir(started_in)
    monkeypatch.setenv(FIGURES_ENV, str(folder))
    submit_quick(db, 2)
    finish_all(db)

    async def scenario() -> None:
        app = app_for(db)
        assert app.figure_folder == folder
        async with app.run_test(size=(80, 24)) as pilot:
            await wait_until(pilot, lambda: app.screen.query("#bifurcation")
                             and app.screen.query_one("#bifurcation").diagram is not None)
            sweep = app.screen.selected
            await pilot.press("f")
            figure = folder / f"sweep-{sweep}.pdf"
            await wait_until(pilot, figure.exists, SETTLE_S)
            await wait_until(pilot, lambda: any("figure written" in n.message for n in app._notifications))
            notes = [n.message for n in app._notifications]
            assert any(f"figure written: {figure} (its data: sweep-{sweep}.csv)" in m for m in notes), notes
            assert figure.read_bytes().startswith(b"%PDF")
            assert list(started_in.iterdir()) == []  # nothing left in the checkout

    run(scenario)
