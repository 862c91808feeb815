"""The application's figures name what they were computed at, as `slopetui figure` does:
the sweep's figure key (f) writes its engine's digest, read from the store, into the
comment line of its CSV and the PDF's metadata (Pilot, 80x24)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

import slopetui
from core.jit_cache import source_digest
from slopetui.figures.output import FACTS_PREFIX
from slopetui.store.database import Database
from slopetui.tui.figure_writing import FIGURES_ENV
from tests.support import finish_all, submit_quick
from tests.tui.support import run, wait_until
from tests.tui.test_tui_app import app_for
from tests.tui.test_tui_figure_folder import SETTLE_S


def test_the_figure_key_names_the_sweeps_engine(db: Database, tmp_path: Path,
                                                monkeypatch: pytest.MonkeyPatch) -> None:
    folder = tmp_path / "figures"
    monkeypatch.setenv(FIGURES_ENV, str(folder))
    submit_quick(db, 2)
    finish_all(db)

    async def scenario() -> None:
        app = app_for(db)
        async with app.run_test(size=(80, 24)) as pilot:
            await wait_until(pilot, lambda: app.screen.query("#bifurcation")
                             and app.screen.query_one("#bifurcation").diagram is not None)
            sweep = app.screen.selected
            await pilot.press("f")
            data = folder / f"sweep-{sweep}.csv"
            await wait_until(pilot, lambda: any("figure written" in n.message
                                                for n in app._notifications), SETTLE_S)
            first = data.read_text(encoding="utf-8").splitlines()[0]
            assert first.startswith(FACTS_PREFIX)
            facts = json.loads(first.removeprefix(FACTS_PREFIX))
            assert facts["sweep"] == sweep and facts["varied"] == ["k"]
            assert facts["engine"] == {"version": slopetui.__version__, "digest": source_digest()}
            assert source_digest().encode() in (folder / f"sweep-{sweep}.pdf").read_bytes()

    run(scenario)
