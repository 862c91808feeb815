"""Fixtures shared by every tier (unit/, integration/, tui/), and the tiers' `slow` marker;
the helpers are in tests/support.py."""

from __future__ import annotations

from pathlib import Path

import pytest

from slopetui.store import Database, open_store
from slopetui.sweeps.spec import parse_spec
from slopetui.sweeps.submit import submit
from tests.support import ADAPTIVE_PLANE, EVIL, QUICK_SOLVER, finish_adaptive

TESTS = Path(__file__).resolve().parent
#: Real processes (integration/) and Textual Pilot scenarios (tui/) take seconds a test:
#: all of them are `slow`, out of the fast loop `pytest -m "not slow"` (pyproject.toml).
SLOW_TIERS = {"integration", "tui"}


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    for item in items:
        path = item.path.resolve()
        if path.is_relative_to(TESTS) and path.relative_to(TESTS).parts[0] in SLOW_TIERS:
            item.add_marker(pytest.mark.slow)


@pytest.fixture
def db_url(tmp_path: Path) -> str:
    return f"sqlite:///{tmp_path / 'store.db'}"


@pytest.fixture
def db(db_url: str) -> Database:
    database = open_store(db_url)
    yield database
    database.dispose()


@pytest.fixture(scope="module")
def refined(tmp_path_factory) -> tuple[str, int]:
    """A store holding ADAPTIVE_PLANE refined to the end (one per test module)."""
    url = f"sqlite:///{tmp_path_factory.mktemp('adaptive') / 'store.db'}"
    db = open_store(url)
    out = submit(db, parse_spec(ADAPTIVE_PLANE))
    assert out.n_runs == 12 and out.n_points == 13 * 9  # the coarse lattice: 4 x 3
    finish_adaptive(db, out.sweep_id)
    db.dispose()
    return url, out.sweep_id


@pytest.fixture
def evil_sweep(db):
    """A sweep whose name an older tool stored with escapes (parse_spec reads it back)."""
    spec = parse_spec({"name": EVIL, "x": {"param": "k", "start": 4, "stop": 12, "num": 3},
                       "solver": QUICK_SOLVER})
    return submit(db, spec).sweep_id
