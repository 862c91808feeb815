"""Fixtures shared by every tier (unit/, integration/, tui/), the tiers' `slow` marker, and
the backends: the helpers are in tests/support.py.

The store, queue and pool tests run on SQLite and on PostgreSQL: they take ``store`` (or
``store_url``, ``new_store_url``), which stand on ``backend``, parametrised over both. The
PostgreSQL case needs a server, named by $SLOPETUI_TEST_PG (.ci/run starts one, so CI runs
both); without it that case is skipped. ``db`` and ``db_url`` are a SQLite store: for the
tests about SQLite's file itself (marked ``sqlite_only``) and for the modules whose subject
is not the store (the CLI, the TUI, sweeps, reports).
"""

from __future__ import annotations

import os
import sqlite3
from collections.abc import Iterator
from pathlib import Path

import pytest

from slopetui.store.database import Database
from slopetui.store.open import open_store
from slopetui.sweeps.spec import parse_spec
from slopetui.sweeps.submit import submit
from tests.support import (
    ADAPTIVE_PLANE,
    EVIL,
    QUICK_SOLVER,
    PgServer,
    finish_adaptive,
    new_sqlite_store,
)

TESTS = Path(__file__).resolve().parent
#: Real processes (integration/) and Textual Pilot scenarios (tui/) take seconds a test:
#: all of them are `slow`, out of the fast loop `pytest -m "not slow"` (pyproject.toml).
SLOW_TIERS = {"integration", "tui"}
#: Several processes (`pytest -n 2`): the slow tiers in one group, the unit tier beside it.
pytest_plugins = ["tests.xdist_plan"]


#: The PostgreSQL server the `postgresql` case runs on (a role that may create databases).
PG_ENV = "SLOPETUI_TEST_PG"
NO_PG = "no PostgreSQL server: set SLOPETUI_TEST_PG (.ci/run starts one)"
#: The PostgreSQL case is also `slow`: the fast loop (`-m "not slow"`, under a minute) runs
#: each store and queue test once, on SQLite; the full suite (CI) runs both backends.
BACKENDS = [pytest.param("sqlite", id="sqlite"),
            pytest.param("postgresql", id="postgresql",
                         marks=[pytest.mark.postgres, pytest.mark.slow])]


def pytest_configure(config: pytest.Config) -> None:
    config.addinivalue_line("markers", "postgres: the PostgreSQL case of a test on both "
                            "backends (the `backend` fixture: store, store_url, "
                            f"new_store_url; also slow); skipped unless ${PG_ENV} names a server")
    config.addinivalue_line("markers", "sqlite_only: about SQLite's file itself (WAL, locks, "
                            "PRAGMAs, file permissions, backups, the default file): runs on "
                            "SQLite only, on purpose")


def pytest_ignore_collect(collection_path: Path, config: pytest.Config) -> bool | None:
    """The fast loop (exactly `-m "not slow"`) does not even import the slow tiers, whose
    every test it would deselect: ~1 s of imports and assertion rewriting saved."""
    if (config.getoption("markexpr", "").strip() == "not slow"
            and collection_path.parent == TESTS and collection_path.name in SLOW_TIERS):
        return True
    return None


@pytest.hookimpl(tryfirst=True)  # before xdist's worker reads the groups into the test ids
def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    from tests.xdist_plan import COMPUTATION, SERIAL_GROUP, WALL_CLOCK  # pytest imports its plugins itself

    for item in items:
        path = item.path.resolve()
        if path.is_relative_to(TESTS) and path.relative_to(TESTS).parts[0] in SLOW_TIERS:
            item.add_marker(pytest.mark.slow)
            if item.get_closest_marker(COMPUTATION):  # beside the group, a module together
                item.add_marker(pytest.mark.xdist_group(f"{COMPUTATION}:{path.stem}"))
            else:
                item.add_marker(pytest.mark.xdist_group(SERIAL_GROUP))  # one process, in turn
        elif item.get_closest_marker(WALL_CLOCK):
            item.add_marker(pytest.mark.xdist_group(SERIAL_GROUP))


@pytest.fixture(scope="session")
def sqlite_template(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A new SQLite store at the current schema, made once a session: ``db`` and ``store``
    start from a copy of it (~3 ms), as the PostgreSQL case starts from a template database,
    where migrating each new file took ~0.1 s (200 new stores: 17 s of the fast loop). The
    copy is what open_store leaves of a new file: the database (mode 600, in WAL mode) and
    the migration's lock file beside it. The first migration of a new file is still tested
    (``new_store_url``, and every test that opens a ``db_url`` itself). A test that makes
    stores of its own takes this fixture and tests.support.new_sqlite_store."""
    path = tmp_path_factory.mktemp("template") / "store.db"
    open_store(f"sqlite:///{path}").dispose()
    with sqlite3.connect(path) as conn:  # everything in the file itself, not in a -wal
        conn.execute("PRAGMA wal_checkpoint(TRUNCATE)")
    conn.close()
    return path


@pytest.fixture
def db_url(tmp_path: Path) -> str:
    """A new SQLite file (on SQLite only: see the module docstring): not created yet."""
    return f"sqlite:///{tmp_path / 'store.db'}"


@pytest.fixture
def db(db_url: str, sqlite_template: Path) -> Iterator[Database]:
    """The store at ``db_url``, at the current schema: SQLite only."""
    new_sqlite_store(db_url, sqlite_template)
    database = open_store(db_url)
    yield database
    database.dispose()


@pytest.fixture(scope="session")
def pg_server() -> Iterator[PgServer]:
    """This pytest process's databases on $SLOPETUI_TEST_PG (named by its pid, so that
    processes running at once never share one)."""
    url = os.environ.get(PG_ENV)
    if not url:
        pytest.skip(NO_PG)
    server = PgServer(url, f"slopetui_test_{os.getpid()}")
    yield server
    server.close()


@pytest.fixture(params=BACKENDS)
def backend(request: pytest.FixtureRequest) -> str:
    """The backend a test on both runs on: "sqlite", or "postgresql" (skipped without a
    server). ``store``, ``store_url`` and ``new_store_url`` are on it."""
    if request.param == "postgresql" and not os.environ.get(PG_ENV):
        pytest.skip(NO_PG)
    return request.param


@pytest.fixture
def store_url(backend: str, request: pytest.FixtureRequest, tmp_path: Path) -> Iterator[str]:
    """A store of the test's own, for other processes as well: a new SQLite file (created
    and migrated when first opened), or a PostgreSQL database already at the current
    schema (a copy of a template migrated once a session), dropped after the test with
    whatever is still connected to it."""
    if backend == "sqlite":
        yield f"sqlite:///{tmp_path / 'store.db'}"
        return
    with request.getfixturevalue("pg_server").database() as url:
        yield url


@pytest.fixture
def new_store_url(backend: str, request: pytest.FixtureRequest,
                  tmp_path: Path) -> Iterator[str]:
    """A database with no schema yet (for the tests of the first migration): a new SQLite
    file, or an empty PostgreSQL database."""
    if backend == "sqlite":
        yield f"sqlite:///{tmp_path / 'new.db'}"
        return
    with request.getfixturevalue("pg_server").database(migrated=False) as url:
        yield url


@pytest.fixture
def store(backend: str, request: pytest.FixtureRequest) -> Iterator[Database]:
    """A store open at the current schema, on SQLite and PostgreSQL: the one at
    ``store_url`` if the test takes that too (as a test must whose store other processes
    use). Otherwise, on PostgreSQL, this process's shared database emptied for the test
    (its ids start from 1, as a new store's): 0.06 s, where a database of its own costs
    0.2 to 0.5 s."""
    if backend == "postgresql" and "store_url" not in request.fixturenames:
        url = request.getfixturevalue("pg_server").emptied_shared()
    else:
        url = request.getfixturevalue("store_url")
    if backend == "sqlite":
        new_sqlite_store(url, request.getfixturevalue("sqlite_template"))
    database = open_store(url)
    yield database
    database.dispose()


@pytest.fixture(scope="module")
def refined(tmp_path_factory, sqlite_template) -> tuple[str, int]:
    """A store holding ADAPTIVE_PLANE refined to the end (one per test module)."""
    url = f"sqlite:///{tmp_path_factory.mktemp('adaptive') / 'store.db'}"
    new_sqlite_store(url, sqlite_template)
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
