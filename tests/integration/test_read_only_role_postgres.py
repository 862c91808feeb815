"""The read-only console on PostgreSQL: what a READ ONLY transaction lets by (signalling
the workers' backends, advisory locks, NOTIFY, DO) is refused before it runs
(slopetui.store.pg_read_guard), and the reading role (slopetui.ops.local_server's
reader_grants, what `db serve` makes) can do none of it even past slopetui.

Skipped unless $SLOPETUI_TEST_PG names a PostgreSQL server as a superuser (.ci/run
starts one; it trusts local connections, so the test's roles need no password).
"""

from __future__ import annotations

import os
import stat
import subprocess
import sys
from collections.abc import Iterator

import pytest
from sqlalchemy import create_engine
from sqlalchemy.engine import make_url

from slopetui.ops.local_server import reader_grants
from slopetui.store.database import Database
from slopetui.store.location import READ_DB_ENV
from slopetui.store.open import open_store
from slopetui.store.read_query import QueryError, ReadQuery
from tests.integration.test_db_serve import free_port, runner  # noqa: F401  (a fixture)
from tests.support import pg_database, submit_quick

PG_URL = os.environ.get("SLOPETUI_TEST_PG")
psycopg = pytest.importorskip("psycopg")
pytestmark = pytest.mark.skipif(not PG_URL, reason="set SLOPETUI_TEST_PG to a PostgreSQL URL")

VICTIM = "slopetui test victim"


@pytest.fixture(scope="module")
def pg_store() -> Iterator[str]:
    assert PG_URL is not None
    with pg_database(PG_URL, f"slopetui_guard_{os.getpid()}") as url:
        db = open_store(url)
        submit_quick(db, 3)
        db.dispose()
        yield url


def libpq(url: str) -> dict[str, object]:
    """psycopg.connect's arguments for a SQLAlchemy URL."""
    u = make_url(url)
    return {"host": u.query.get("host", u.host), "port": u.query.get("port", u.port),
            "user": u.username, "dbname": u.database, "password": u.password,
            "autocommit": True}


def read_all(engine, sql: str) -> list[tuple]:
    with ReadQuery(sql, timeout_s=10).execute(engine) as rows:
        return [row for chunk in rows.chunks() for row in chunk]


ATTACKS = [
    f"SELECT pg_terminate_backend(pid) FROM pg_stat_activity WHERE application_name = '{VICTIM}'",
    f"SELECT pg_catalog.\"pg_cancel_backend\"(pid) FROM pg_stat_activity "
    f"WHERE application_name = '{VICTIM}'",
    "SELECT pg_advisory_lock(31)", "select PG_TRY_ADVISORY_LOCK(31)",
    "/* first */ -- a comment\n SELECT pg_advisory_xact_lock_shared(31)",
    "DO $$BEGIN PERFORM pg_terminate_backend(pid) FROM pg_stat_activity "
    f"WHERE application_name = '{VICTIM}'; END$$",
    "NOTIFY slopetui, 'x'", "SELECT pg_notify('slopetui', 'x')",
    "SELECT query_to_xml('SELECT pg_' || 'terminate_backend(1)', true, false, '')",
    'SELECT U&"pg\\005fterminate_backend"(1)',
    "SET ROLE NONE", "COPY runs TO STDOUT",
    "SELECT set_config('statement_timeout', '0', false)",
]


@pytest.mark.parametrize("sql", ATTACKS)
def test_what_read_only_lets_by_is_refused(pg_store: str, sql: str) -> None:
    """The victim, a connection of the same role as the console, lives on; no advisory
    lock is held afterwards."""
    victim = psycopg.connect(**libpq(pg_store), application_name=VICTIM)
    db = Database(pg_store)
    engine = db.read_only_engine()
    try:
        with pytest.raises(QueryError) as refused:
            read_all(engine, sql)
        assert refused.value.refused, refused.value.message
        assert victim.execute("SELECT 1").fetchone() == (1,)
        # in this test's own database: a migration of another test's database (the other
        # xdist process) holds its advisory lock for a moment on the same server
        assert read_all(engine, "SELECT count(*) FROM pg_locks WHERE locktype = 'advisory' "
                        "AND database = (SELECT oid FROM pg_database "
                        "WHERE datname = current_database())") == [(0,)]
    finally:
        engine.dispose()
        db.dispose()
        victim.close()


def test_reads_still_run(pg_store: str) -> None:
    db = Database(pg_store)
    engine = db.read_only_engine()
    try:
        assert read_all(engine, "SELECT count(*) FROM runs") == [(3,)]
        assert read_all(engine, "  -- the runs\n(SELECT count(*) FROM runs)") == [(3,)]
        assert read_all(engine, "WITH r AS (SELECT k FROM runs) SELECT max(k) FROM r") == [(12.0,)]
        assert read_all(engine, "TABLE alembic_version")
        assert read_all(engine, "EXPLAIN SELECT * FROM runs")
        assert read_all(engine, "VALUES (1)") == [(1,)]
        assert read_all(engine, "SHOW transaction_read_only") == [("on",)]
    finally:
        engine.dispose()
        db.dispose()


def test_the_cli_refuses_in_one_line_and_exits_2(pg_store: str) -> None:
    victim = psycopg.connect(**libpq(pg_store), application_name=VICTIM)
    try:
        done = subprocess.run([sys.executable, "-m", "slopetui", "sql", ATTACKS[0], "--db",
                               pg_store], capture_output=True, text=True, timeout=120)
        assert done.returncode == 2 and done.stdout == ""
        assert done.stderr == ("slopetui sql: refused: the store is opened read-only "
                               "(pg_terminate_backend() acts beyond a read (other sessions, "
                               "locks, settings, the server's files, SQL given as text): a "
                               "read-only query may not call it)\n")
        assert victim.execute("SELECT 1").fetchone() == (1,)
    finally:
        victim.close()


@pytest.fixture
def roles() -> Iterator[tuple[str, str]]:
    """A workers' role (no superuser) owning a migrated store, and a reading role made by
    reader_grants: their URLs."""
    assert PG_URL is not None
    pid = os.getpid()
    owner, reader, name = f"slopetui_w_{pid}", f"slopetui_r_{pid}", f"slopetui_roles_{pid}"
    admin = create_engine(PG_URL, isolation_level="AUTOCOMMIT")
    base = make_url(PG_URL)
    with admin.connect() as conn:
        conn.exec_driver_sql(f"DROP DATABASE IF EXISTS {name} WITH (FORCE)")
        for role in (reader, owner):
            conn.exec_driver_sql(f"DROP ROLE IF EXISTS {role}")
            conn.exec_driver_sql(f"CREATE ROLE {role} LOGIN")
        conn.exec_driver_sql(f"CREATE DATABASE {name} OWNER {owner}")
    owner_url = base.set(username=owner, password=None, database=name).render_as_string(
        hide_password=False)
    reader_url = base.set(username=reader, password=None, database=name).render_as_string(
        hide_password=False)
    db = open_store(owner_url)  # migrated by the workers' role, which owns the tables
    submit_quick(db, 3)
    db.dispose()
    super_in_db = create_engine(base.set(database=name), isolation_level="AUTOCOMMIT")
    with super_in_db.connect() as conn:
        for statement in reader_grants(owner, reader, name):
            conn.exec_driver_sql(statement)
    super_in_db.dispose()
    try:
        yield owner_url, reader_url
    finally:
        with admin.connect() as conn:
            conn.exec_driver_sql(f"DROP DATABASE IF EXISTS {name} WITH (FORCE)")
            for role in (reader, owner):
                conn.exec_driver_sql(f"DROP ROLE IF EXISTS {role}")
        admin.dispose()


def test_the_reading_role_reads_and_can_do_nothing_else(roles) -> None:
    owner_url, reader_url = roles
    worker = psycopg.connect(**libpq(owner_url), application_name=VICTIM)
    reader = psycopg.connect(**libpq(reader_url))
    try:
        assert reader.execute("SELECT count(*) FROM runs").fetchone() == (3,)
        # a table a later migration adds (made by the workers' role) is readable too
        worker.execute("CREATE TABLE later (x int)")
        assert reader.execute("SELECT count(*) FROM later").fetchone() == (0,)
        # the workers still take their advisory locks
        assert worker.execute("SELECT pg_try_advisory_lock(5)").fetchone() == (True,)
        worker_pid = worker.info.backend_pid
        for sql, error in (("DELETE FROM runs", "permission denied"),
                           ("CREATE TABLE mine (x int)", "permission denied"),
                           ("SELECT pg_advisory_lock(6)", "permission denied"),
                           ("SELECT pg_try_advisory_xact_lock(6)", "permission denied"),
                           (f"SELECT pg_terminate_backend({worker_pid})", "must be a member|permission denied"),
                           (f"SELECT pg_cancel_backend({worker_pid})", "must be a member|permission denied")):
            with pytest.raises(psycopg.Error, match=error):
                reader.execute(sql)
        assert worker.execute("SELECT count(*) FROM runs").fetchone() == (3,)  # alive
    finally:
        reader.close()
        worker.close()


def test_slopetui_reads_under_the_reading_role_when_named(roles, monkeypatch) -> None:
    owner_url, reader_url = roles
    monkeypatch.setenv(READ_DB_ENV, reader_url)
    db = Database(owner_url)
    engine = db.read_only_engine()
    try:
        assert read_all(engine, "SELECT current_user") == [(make_url(reader_url).username,)]
    finally:
        engine.dispose()
    # a reader of another database is not used: its rows would pass for this store's
    monkeypatch.setenv(READ_DB_ENV, make_url(reader_url).set(database="postgres")
                       .render_as_string(hide_password=False))
    engine = db.read_only_engine()
    try:
        assert read_all(engine, "SELECT current_user") == [(make_url(owner_url).username,)]
    finally:
        engine.dispose()
        db.dispose()


def test_db_serve_makes_the_reading_role(runner) -> None:  # noqa: F811  (the fixture)
    """`slopetui db serve` makes slopetui_read with its own password and URL (DIR/read-url,
    mode 600); over TCP it reads, and is refused the workers' locks and backends; the
    commands that read run under it when SLOPETUI_READ_DB names it."""
    folder, port = runner.home / "pg", free_port()
    serve = runner.serve("--dir", str(folder), "--port", str(port))
    try:
        serve.ready()
        read_url = (folder / "read-url").read_text().strip()
        worker_url = (folder / "url").read_text().strip()
        assert stat.S_IMODE((folder / "read-url").stat().st_mode) == 0o600
        assert stat.S_IMODE((folder / "read-password").stat().st_mode) == 0o600
        reader_pw = (folder / "read-password").read_text().strip()
        assert read_url.startswith(f"postgresql+psycopg://slopetui_read:{reader_pw}@")
        assert reader_pw != (folder / "password").read_text().strip()
        here = make_url(worker_url).set(host="127.0.0.1")
        db = Database(here.render_as_string(hide_password=False))
        submit_quick(db, 3)
        db.dispose()
        worker = psycopg.connect(**libpq(here.render_as_string(hide_password=False)))
        reader = psycopg.connect(**libpq(make_url(read_url).set(host="127.0.0.1")
                                         .render_as_string(hide_password=False)))
        try:
            assert reader.execute("SELECT count(*) FROM runs").fetchone() == (3,)
            assert worker.execute("SELECT pg_try_advisory_lock(5)").fetchone() == (True,)
            for sql in ("DELETE FROM runs", "SELECT pg_advisory_lock(6)",
                        f"SELECT pg_terminate_backend({worker.info.backend_pid})"):
                with pytest.raises(psycopg.Error, match=r"must be a member|permission denied"):
                    reader.execute(sql)
        finally:
            reader.close()
            worker.close()
        env = {**runner.env, "SLOPETUI_DB": here.render_as_string(hide_password=False),
               READ_DB_ENV: make_url(read_url).set(host="127.0.0.1")
               .render_as_string(hide_password=False)}
        runner.env, before = env, runner.env
        try:
            done = runner.run("sql", "SELECT current_user", "--csv")
        finally:
            runner.env = before
        assert done.returncode == 0 and done.stdout == "current_user\nslopetui_read\n", done
    finally:
        runner.run("db", "serve", "--dir", str(folder), "--stop")
        serve.rest()
