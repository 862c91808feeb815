"""`slopetui worker` options, `--detach` refusing a second pool, `slopetui workers`,
`slopetui worker --stop [--now]`, the log's permissions and the warm-up's messages.

Pools on another host run on SQLite and PostgreSQL (``store``). The detached pool runs on
SQLite only, for time (on both it doubled the module's): what its stop does to the store
(runs given back, worker rows stopped) is test_worker_signals.py's, on both."""

from __future__ import annotations

import json
import logging
import os
import re
import signal
import socket
import stat
import threading
import time

import pytest
from sqlalchemy import select

from slopetui.cli import main
from slopetui.store.models import Run, Worker
from tests.integration.pool_support import LONG, gone, live_worker_rows, started_run, wait_until
from tests.support import submit_quick


@pytest.fixture(autouse=True)
def private_state(tmp_path, monkeypatch):
    """Pool files in the test's folder (platformdirs reads XDG_STATE_HOME at each call)."""
    monkeypatch.setenv("XDG_STATE_HOME", str(tmp_path / "state"))


@pytest.mark.parametrize("args, error", [
    (["--heartbeat", "inf", "--lease", "inf"],
     "--heartbeat must be a finite number of seconds from 0.1 to 600, got inf"),
    (["--heartbeat", "nan"], "--heartbeat must be a finite number of seconds"),
    (["--heartbeat", "0"], "--heartbeat must be"),
    (["--lease", "inf"], "--lease must be a finite number of seconds (at least 2 x "
                         "--heartbeat) from 20 to 86400, got inf"),
    (["--lease", "5"], "--lease must be"),
    (["-j", "0"], "--jobs must be a finite number from 1 to 512, got 0"),
    (["--batch", "0"], "--batch must be a finite number from 1 to 256"),
    (["--batch", "257"], "--batch must be"),
    (["--max-attempts", "0"], "--max-attempts must be a finite number from 1 to 100"),
    (["--memory", "10"], "--memory must be a finite number of MiB from 64 to 524288, got 10"),
    (["--now"], "--now goes with --stop"),
])
def test_bad_numbers_are_refused_with_one_line(tmp_path, capsys, args, error):
    # --exit-when-idle -j 1: were the option accepted, the pool would stop on its own
    base = ["worker", "--db", f"sqlite:///{tmp_path / 's.db'}", "--exit-when-idle"]
    status = main([*base, *([] if "-j" in args else ["-j", "1"]), *args])
    err = capsys.readouterr().err
    assert status == 2
    assert err.startswith(f"slopetui worker: error: {error}") and err.count("\n") == 1, err


def test_the_log_is_created_readable_by_its_owner_only(tmp_path):
    from slopetui.queue.worker_process import configure_logging

    log = tmp_path / "worker.log"
    try:
        configure_logging(str(log))
        logging.getLogger("slopetui.test").info("hello")
    finally:
        logging.getLogger("slopetui").handlers.clear()
    assert stat.S_IMODE(log.stat().st_mode) == 0o600 and "hello" in log.read_text()


def test_a_slow_warm_up_says_it_compiles_and_how_long_it_took(monkeypatch, caplog):
    from slopetui.queue import warm_up

    monkeypatch.setattr(warm_up, "warm_up", lambda: time.sleep(0.5))
    monkeypatch.setattr(warm_up, "COMPILING_AFTER_S", 0.1)
    with caplog.at_level(logging.INFO, logger="slopetui"):
        took = warm_up.watched_warm_up(lambda: False)
    assert took >= 0.5
    # no figure that goes stale (it said ~30 s; 19-20 s on two idle cores, more on busy
    # ones): the time it took comes when it is done
    assert ("compiling the numba kernels, once (first run after an install or an engine "
            "change; cached afterwards)") in caplog.text
    assert re.search(r"numba kernels compiled in \d+\.\d s", caplog.text)


def test_a_detached_pool_is_listed_refuses_a_second_one_and_stops(tmp_path, db, db_url, capsys):
    submit_quick(db, 1, **LONG)
    log = tmp_path / "logs" / "worker.log"
    common = ["--db", db_url]
    assert main(["worker", "--detach", "-j", "1", "--log", str(log), "--heartbeat", "0.5",
                 "--lease", "3", *common]) == 0
    pid = int(re.search(r"pid (\d+)", capsys.readouterr().out).group(1))
    try:
        assert stat.S_IMODE(log.stat().st_mode) == 0o600
        # at once, while it still starts: known from its pool file
        assert main(["worker", "--detach", *common]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and f"already runs on this host: pid {pid}" in err
        assert "slopetui worker --stop" in err and "--another-pool" in err
        assert main(["worker", "-j", "1", *common]) == 2  # nor in the foreground
        assert f"pid {pid}" in capsys.readouterr().err

        run = wait_until("the run in a kernel", lambda: started_run(db))
        assert main(["workers", *common]) == 0
        out = capsys.readouterr().out
        assert re.search(rf"pool {pid} on \S+ \(this host\), up [^,]+, 1 workers; log ", out)
        assert re.search(rf"worker {re.escape(run.worker_id)} +run {run.id} +0 done  "
                         r"heartbeat \d+ s ago", out), out
        assert main(["workers", "--json", *common]) == 0
        listed = json.loads(capsys.readouterr().out)
        assert [(p["pid"], [w["run_id"] for w in p["workers"]]) for p in listed["pools"]] \
            == [(pid, [run.id])]

        graceful: list[int] = []  # `worker --stop` waits for the ~7 s run ...
        waiter = threading.Thread(target=lambda: graceful.append(
            main(["worker", "--stop", *common])))
        waiter.start()
        time.sleep(1.0)
        assert waiter.is_alive() and not gone(pid)
        t0 = time.monotonic()
        assert main(["worker", "--stop", "--now", *common]) == 0  # ... --now ends it
        waiter.join(30)
        assert graceful == [0] and time.monotonic() - t0 < 10
    finally:
        if not gone(pid):
            os.kill(pid, signal.SIGKILL)
    out = capsys.readouterr().out
    assert f"stopping pool {pid} (1 workers; the runs being computed finish first)" in out
    assert f"waiting for pool {pid}: {run.worker_id} on run {run.id}" in out
    assert f"stopping pool {pid} (1 workers; now: the running runs go back" in out
    assert f"pool {pid} stopped" in out
    assert gone(pid) and live_worker_rows(db) == []
    with db.sessions() as s:  # given back, the attempt not counted
        assert [(r.status, r.attempts) for r in s.scalars(select(Run))] == [("queued", 0)]
    assert main(["workers", *common]) == 0
    assert "no worker pool of this store is running" in capsys.readouterr().out


def test_pools_on_another_host_are_listed_and_not_signalled(store, store_url, capsys):
    with store.transaction() as s:
        s.add(Worker(id="elsewhere:4242", host="elsewhere", pid=4242))
    assert main(["workers", "--db", store_url]) == 0
    out = capsys.readouterr().out
    assert "workers on elsewhere (another host: their pool's pid is not known here)" in out
    assert "worker elsewhere:4242" in out and "idle" in out
    assert main(["worker", "--stop", "--db", store_url]) == 0
    captured = capsys.readouterr()
    assert (f"1 workers of this store run on elsewhere: they cannot be signalled from "
            f"{socket.gethostname()}; run `slopetui worker --stop` on elsewhere") in captured.err
    assert "no worker pool of this store runs on" in captured.out
