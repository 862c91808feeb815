"""Helpers shared by the tests of every tier (fixtures stay in conftest.py).

Light to import (the engine, with numba and scipy, ~1 s, only inside finish_all): the
processes that multiprocessing spawns from a test module import that module, and this
one with it (tests/integration/test_store_processes.py).
"""

from __future__ import annotations

import itertools
import os
import shutil
import subprocess
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from sqlalchemy import Engine

    from slopetui.queue.jobs import Job
    from slopetui.store.database import Database
    from slopetui.sweeps.submit import Submitted

#: A cheap point: RK4, tau = 2, t_end = 200, a few ms per run.
QUICK_SOLVER = {"method": "rk4", "dt": 0.01, "t_end": 200.0, "window": 100.0}

#: A small (k, tau) plane with sliding, oscillatory and complex regions (13 x 9 points),
#: refined adaptively twice, with cheap runs (no lambda_max).
ADAPTIVE_PLANE = {"name": "adaptive (k, tau)",
                  "x": {"param": "k", "start": 2, "stop": 20, "num": 13},
                  "y": {"param": "tau", "start": 0.5, "stop": 10, "num": 9},
                  "adaptive": {"levels": 2}, "solver": {**QUICK_SOLVER, "lyap": False}}

#: A name that clears the screen, turns the terminal red, and reverses what follows.
EVIL = "\x1b[2J\x1b[31mevil\u202eabc"

#: A statement that computes for about a minute on a 2-core box (about 180 ns a row), so
#: that a broken limit or cancel fails a test rather than hanging it.
SLOW = ("WITH RECURSIVE c(x) AS (SELECT 1 UNION ALL SELECT x + 1 FROM c "
        "WHERE x < 300000000) SELECT count(*) FROM c")
#: Rows without end, produced quickly.
ENDLESS = "WITH RECURSIVE c(x) AS (SELECT 1 UNION ALL SELECT x + 1 FROM c) SELECT x FROM c"


def submit_quick(db: Database, n: int = 5, *, tau: float = 2.0, **solver: object) -> Submitted:
    """A 1-D sweep over k with n cheap runs."""
    from slopetui.sweeps.spec import parse_spec
    from slopetui.sweeps.submit import submit

    spec = parse_spec({"x": {"param": "k", "start": 4, "stop": 12, "num": n},
                       "fixed": {"tau": tau}, "solver": {**QUICK_SOLVER, **solver}})
    return submit(db, spec)


def slopetui_cli(*args: str, env: dict[str, str] | None = None, cwd: str | None = None,
                 timeout: float = 300) -> subprocess.CompletedProcess[str]:
    """`python -m slopetui ARGS` in a fresh process, as a user would type it."""
    return subprocess.run([sys.executable, "-m", "slopetui", *args], capture_output=True,
                          text=True, timeout=timeout, env={**os.environ, **(env or {})},
                          cwd=cwd)


def new_sqlite_store(url: str, template: Path) -> None:
    """Make the SQLite file of ``url`` a copy of the store ``template`` (the ``sqlite_template``
    fixture: a new store at the current schema), unless the file exists already: what
    open_store leaves of a new file (the database, mode 600, and the migration's lock file
    beside it) in ~3 ms, where migrating a new file takes ~0.1 s."""
    path = Path(url.removeprefix("sqlite:///"))
    if path.exists():
        return
    for source in template.parent.glob(f"{template.name}*"):
        if not source.name.endswith(("-wal", "-shm")):
            shutil.copy2(source, path.with_name(path.name + source.name[len(template.name):]))


def claim_one(db: Database, worker: str) -> Job | None:
    """The oldest queued run of an active sweep, claimed and begun (one attempt charged,
    the worker pointed at it), or None: the batch claim with a batch of 1, as a worker
    claims a run computed alone."""
    from slopetui.queue import jobs

    return next(iter(jobs.begin(db, jobs.claim_batch(db, worker, 1), worker)), None)


def finish_all(db: Database, worker: str = "test") -> int:
    """Compute every queued run in this process, as a worker would; returns how many."""
    from core.point import run_point
    from slopetui.queue import jobs

    n = 0
    while (job := claim_one(db, worker)) is not None:
        record = run_point(job.params, job.settings, job.carried).as_record()
        jobs.complete(db, job, worker, record)
        n += 1
    return n


def finish_adaptive(db: Database, sweep_id: int, worker: str = "test") -> int:
    """Compute an adaptive sweep level by level in this process, advancing it as an idle
    worker would, until it is refined; returns the runs computed."""
    from slopetui.store.models import Sweep
    from slopetui.sweeps.adaptive import advance

    n = 0
    for _ in range(20):  # more than the 8 levels allowed, plus slack
        n += finish_all(db, worker)
        advance(db, sweep_id)
        with db.sessions() as s:
            if s.get(Sweep, sweep_id).refined:
                return n
    raise AssertionError(f"adaptive sweep {sweep_id} did not finish refining")


@contextmanager
def pg_database(server_url: str, name: str) -> Iterator[str]:
    """A database ``name`` of its own on the PostgreSQL server at ``server_url`` (a role
    that may create databases; .ci/run starts such a server): its URL, dropped afterwards
    (other tests may share the server)."""
    from sqlalchemy import create_engine
    from sqlalchemy.engine import make_url

    admin = create_engine(server_url, isolation_level="AUTOCOMMIT")
    with admin.connect() as conn:
        conn.exec_driver_sql(f"DROP DATABASE IF EXISTS {name}")
        conn.exec_driver_sql(f"CREATE DATABASE {name}")
    try:
        yield make_url(server_url).set(database=name).render_as_string(hide_password=False)
    finally:
        with admin.connect() as conn:
            conn.exec_driver_sql(f"DROP DATABASE IF EXISTS {name} WITH (FORCE)")
        admin.dispose()


class PgServer:
    """Throwaway databases on the PostgreSQL server at ``server_url`` (a role that may
    create databases), named ``<prefix>_...``: give the prefix the process id, so that
    pytest processes sharing the server never meet (tests/conftest.py: the fixtures on
    both backends).

    A database of its own at the current schema (``database()``) is a copy of a template
    migrated once: CREATE DATABASE ... TEMPLATE copies its files, 0.2 s with fsync off
    (0.5 s on a loaded 2-core box), where migrating takes seconds. Nobody may connect to
    the template meanwhile: it refuses connections once migrated. Cheaper still, for the
    tests that use the store in their own process only: one shared database, emptied
    (``emptied_shared()``: TRUNCATE ... RESTART IDENTITY, 0.06 s).
    """

    def __init__(self, server_url: str, prefix: str) -> None:
        from sqlalchemy import create_engine
        from sqlalchemy.engine import make_url

        self.url = make_url(server_url)
        self.prefix = prefix
        self.admin = create_engine(server_url, isolation_level="AUTOCOMMIT")
        self._numbers = itertools.count(1)
        self._template: str | None = None
        self._shared: Engine | None = None  # AUTOCOMMIT, on the shared database

    def url_of(self, name: str) -> str:
        return self.url.set(database=name).render_as_string(hide_password=False)

    def _run(self, *statements: str) -> None:
        with self.admin.connect() as conn:
            for statement in statements:
                conn.exec_driver_sql(statement)

    def template(self) -> str:
        """The template database at the current schema, made on first use."""
        if self._template is None:
            from slopetui.store.open import open_store

            name = f"{self.prefix}_template"
            # (one of the same name is a leftover of a killed pytest with the same pid)
            self._run(f"DROP DATABASE IF EXISTS {name} WITH (FORCE)",
                      f"CREATE DATABASE {name}")
            open_store(self.url_of(name)).dispose()  # migrated; no connection stays
            self._run(f"ALTER DATABASE {name} WITH ALLOW_CONNECTIONS false")
            self._template = name
        return self._template

    @contextmanager
    def database(self, *, migrated: bool = True) -> Iterator[str]:
        """A database of its own, at the current schema (``migrated``) or empty: its URL,
        dropped afterwards with whatever is still connected to it (a killed worker's)."""
        name = f"{self.prefix}_{next(self._numbers)}"
        template = self.template() if migrated else "template0"
        self._run(f"DROP DATABASE IF EXISTS {name} WITH (FORCE)",
                  f"CREATE DATABASE {name} TEMPLATE {template}")
        try:
            yield self.url_of(name)
        finally:
            self._run(f"DROP DATABASE IF EXISTS {name} WITH (FORCE)")

    def emptied_shared(self) -> str:
        """The URL of this process's shared database at the current schema, with no rows
        in it and its ids starting again from 1, as a new store's; any connection left in
        it is closed first."""
        from sqlalchemy import create_engine

        name = f"{self.prefix}_shared"
        if self._shared is None:
            template = self.template()
            self._run(f"DROP DATABASE IF EXISTS {name} WITH (FORCE)",
                      f"CREATE DATABASE {name} TEMPLATE {template}")
            self._shared = create_engine(self.url_of(name), isolation_level="AUTOCOMMIT")
        with self._shared.connect() as conn:
            conn.exec_driver_sql("SELECT pg_terminate_backend(pid) FROM pg_stat_activity "
                                 "WHERE datname = current_database() "
                                 "AND pid <> pg_backend_pid()")
            tables = conn.exec_driver_sql(
                "SELECT quote_ident(tablename) FROM pg_tables WHERE schemaname = 'public' "
                "AND tablename <> 'alembic_version'").scalars().all()
            conn.exec_driver_sql(f"TRUNCATE {', '.join(tables)} RESTART IDENTITY CASCADE")
        return self.url_of(name)

    def close(self) -> None:
        if self._shared is not None:
            self._shared.dispose()
            self._run(f"DROP DATABASE IF EXISTS {self.prefix}_shared WITH (FORCE)")
        if self._template is not None:
            self._run(f"DROP DATABASE IF EXISTS {self._template} WITH (FORCE)")
        self.admin.dispose()
