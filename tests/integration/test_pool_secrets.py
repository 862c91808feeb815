"""The database's password never reaches a command line.

Every user of the machine reads every process's command line (/proc/PID/cmdline, ``ps -eo
args``); a detached pool gets the store's URL in its environment instead
(slopetui.queue.local_pool). Here a detached pool runs on a PostgreSQL database owned by
a role with a password, started both ways a pool is started in the background:
``slopetui worker --detach`` and the function the application calls
(``start_detached_pool``). While it starts, computes a run and stops, every command line
on the machine is read again and again: none may hold the password, and neither may the
pool's log. The Slurm script's exec line is tests/unit/test_slurm_script.py's.

Needs a PostgreSQL server in $SLOPETUI_TEST_PG (a superuser: the test makes a role).
"""

from __future__ import annotations

import os
import re
import secrets
import threading
from collections.abc import Iterator
from pathlib import Path

import pytest
from sqlalchemy import create_engine
from sqlalchemy.engine import make_url

from slopetui.cli import main
from slopetui.queue.local_pool import start_detached_pool, store_key
from slopetui.store.location import DB_ENV
from slopetui.store.open import open_store
from tests.integration.pool_support import by_status, gone, wait_until
from tests.support import submit_quick

PG_URL = os.environ.get("SLOPETUI_TEST_PG")
pytestmark = pytest.mark.skipif(not PG_URL, reason="needs a PostgreSQL server: set "
                                                   "$SLOPETUI_TEST_PG (.ci/run starts one)")


@pytest.fixture
def password_url() -> Iterator[str]:
    """The URL, password included, of a database of its own owned by a role of its own
    that has a password (the server may trust local connections: the password is still in
    the URL, which is what matters here)."""
    assert PG_URL is not None
    name = f"secret_{os.getpid()}"
    password = f"Pw{secrets.token_hex(12)}"
    admin = create_engine(PG_URL, isolation_level="AUTOCOMMIT")

    def drop() -> None:
        with admin.connect() as conn:
            conn.exec_driver_sql(f"DROP DATABASE IF EXISTS {name} WITH (FORCE)")
            conn.exec_driver_sql(f"DROP ROLE IF EXISTS {name}")

    drop()  # a leftover of a killed test with the same pid
    with admin.connect() as conn:
        conn.exec_driver_sql(f"CREATE ROLE {name} LOGIN PASSWORD '{password}'")
        conn.exec_driver_sql(f"CREATE DATABASE {name} OWNER {name}")
    try:
        yield make_url(PG_URL).set(username=name, password=password, database=name
                                   ).render_as_string(hide_password=False)
    finally:
        drop()
        admin.dispose()


def command_lines_holding(secret: bytes) -> list[tuple[int, bytes]]:
    """The processes of the machine (any user's) whose command line holds ``secret``."""
    found = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                command = (entry / "cmdline").read_bytes()
            except OSError:  # exited meanwhile
                continue
            if secret in command:
                found.append((int(entry.name), command))
    return found


class CommandLineWatch:
    """Reads every command line of the machine until stopped, keeping those that hold the
    secret: a process that shows it only for a moment is caught too."""

    def __init__(self, secret: str) -> None:
        self.secret = secret.encode()
        self.found: dict[int, bytes] = {}
        self.scans = 0
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._watch, daemon=True)

    def _watch(self) -> None:
        while not self._stop.is_set():
            self.found.update(command_lines_holding(self.secret))
            self.scans += 1
            self._stop.wait(0.02)

    def __enter__(self) -> CommandLineWatch:
        self._thread.start()
        return self

    def __exit__(self, *_: object) -> None:
        self._stop.set()
        self._thread.join()


@pytest.mark.parametrize("starter", ["worker --detach", "the application's start"])
def test_a_detached_pool_on_a_password_url_shows_it_on_no_command_line(
        starter, password_url, tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("XDG_STATE_HOME", str(tmp_path / "state"))
    monkeypatch.delenv(DB_ENV, raising=False)
    password = make_url(password_url).password
    assert password
    db = open_store(password_url)
    submit_quick(db, 2)
    log = tmp_path / "worker.log"
    with CommandLineWatch(password) as watch:
        if starter == "worker --detach":
            assert main(["worker", "--detach", "-j", "1", "--log", str(log), "--db",
                         password_url]) == 0
            pid = int(re.search(r"pid (\d+)", capsys.readouterr().out).group(1))
        else:  # what SlopeApp.attach_pool does
            pid, _ = start_detached_pool(db, jobs=1, log=log)
        try:
            # right after --detach the pool warms up: it is starting, not absent (item 11a)
            assert main(["status", "--db", password_url]) == 0
            assert "no live workers" not in capsys.readouterr().out
            # the URL reached the pool (in its environment, which only this user reads)
            environ = Path(f"/proc/{pid}/environ").read_bytes().split(b"\0")
            assert f"{DB_ENV}={password_url}".encode() in environ
            wait_until("the runs done", lambda: by_status(db) == {"done": 2}, timeout=180)
            pool_files = list((tmp_path / "state").rglob("*.json"))
            assert [f.name for f in pool_files] == [f"{store_key(password_url)}-{pid}.json"]
            assert password.encode() not in pool_files[0].read_bytes()
            assert main(["worker", "--stop", "--db", password_url]) == 0
            wait_until("the pool gone", lambda: gone(pid), timeout=60)
        finally:
            if not gone(pid):
                os.kill(pid, 9)
    db.dispose()
    assert watch.scans > 10
    assert watch.found == {}, f"the password is on these command lines: {watch.found}"
    text = log.read_text()
    assert "pool of 1 workers on postgresql+psycopg://" in text and ":***@" in text
    assert password not in text
