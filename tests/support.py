"""Helpers shared by the tests of every tier (fixtures stay in conftest.py)."""

from __future__ import annotations

import os
import subprocess
import sys
from collections.abc import Iterator
from contextlib import contextmanager

from core import run_point
from slopetui.queue import jobs
from slopetui.store import Database
from slopetui.sweeps.spec import parse_spec
from slopetui.sweeps.submit import Submitted, submit

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
    spec = parse_spec({"x": {"param": "k", "start": 4, "stop": 12, "num": n},
                       "fixed": {"tau": tau}, "solver": {**QUICK_SOLVER, **solver}})
    return submit(db, spec)


def slopetui_cli(*args: str, env: dict[str, str] | None = None, cwd: str | None = None,
                 timeout: float = 300) -> subprocess.CompletedProcess[str]:
    """`python -m slopetui ARGS` in a fresh process, as a user would type it."""
    return subprocess.run([sys.executable, "-m", "slopetui", *args], capture_output=True,
                          text=True, timeout=timeout, env={**os.environ, **(env or {})},
                          cwd=cwd)


def finish_all(db: Database, worker: str = "test") -> int:
    """Compute every queued run in this process, as a worker would; returns how many."""
    n = 0
    while (job := jobs.claim(db, worker)) is not None:
        record = run_point(job.params, job.settings, jobs.carried_state(db, job)).as_record()
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
