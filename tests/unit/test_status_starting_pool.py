"""`slopetui status` right after `slopetui worker --detach`: the pool warms up (loads or
compiles the kernels) before any worker registers, and `--detach` returns at once, so
`status` names it as starting instead of saying "no live workers".
The pool here is a process recorded in a pool file, as start_detached_pool records one
before it returns; the real detached pool is tests/integration/test_pool_secrets.py's."""

from __future__ import annotations

import json
import subprocess
from collections.abc import Iterator
from pathlib import Path

import pytest

from slopetui.cli import main
from slopetui.queue.local_pool import write_pool_file
from slopetui.store.database import Database


@pytest.fixture
def warming_pool(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                 db: Database) -> Iterator[subprocess.Popen[bytes]]:
    """A live process with a pool file of ``db`` and no worker row."""
    monkeypatch.setenv("XDG_STATE_HOME", str(tmp_path / "state"))
    proc = subprocess.Popen(["sleep", "120"])
    try:
        write_pool_file(db.url.render_as_string(hide_password=False), proc.pid,
                        str(tmp_path / "worker.log"))
        yield proc
    finally:
        proc.kill()
        proc.wait()


def test_a_pool_without_workers_yet_is_starting_not_absent(warming_pool, db_url, capsys):
    assert main(["status", "--db", db_url]) == 0
    out = capsys.readouterr().out
    assert f"pool {warming_pool.pid} on this host: starting, up " in out
    assert "no live workers" not in out


def test_the_json_lists_the_starting_pool(warming_pool, db_url, tmp_path, capsys):
    assert main(["status", "--json", "--db", db_url]) == 0
    listed = json.loads(capsys.readouterr().out)
    assert listed["workers"] == []
    [pool] = listed["starting_pools"]
    assert pool["pid"] == warming_pool.pid and pool["log"] == str(tmp_path / "worker.log")
    assert 0 <= pool["uptime_s"] < 60


def test_once_the_pool_is_gone_there_are_no_live_workers(warming_pool, db_url, capsys):
    warming_pool.kill()  # a pool killed while it warmed up: its file stayed behind
    warming_pool.wait()
    assert main(["status", "--db", db_url]) == 0
    out = capsys.readouterr().out
    assert "no live workers" in out and "starting" not in out
