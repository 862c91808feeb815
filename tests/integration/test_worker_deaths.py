"""The pool stops restarting workers that keep dying, and then exits with status 1 so that
a supervisor (systemd Restart=on-failure) restarts it; deaths spread over time never add
up to that.

The heavy imports are inside the tests: the dying workers import this module (spawn), and
should die fast.
"""

from __future__ import annotations

import logging
import os


def dies_at_once(*_args: object) -> None:
    """A worker of a broken installation: it dies as it starts."""
    os._exit(3)


def test_the_death_window_slides():
    from slopetui.queue.pool import DeathWindow

    burst = DeathWindow(limit=2, window_s=10.0)
    assert [burst.add(t) for t in (0.0, 1.0, 2.0)] == [False, False, True]
    spread = DeathWindow(limit=2, window_s=10.0)  # two deaths in any 10 s, never three
    assert not any(spread.add(t) for t in (0.0, 6.0, 12.0, 18.0, 24.0, 30.0, 36.0))


def test_a_crash_loop_makes_the_pool_give_up_with_status_1(tmp_path, monkeypatch, store_url):
    from slopetui.queue import pool as pool_module
    from slopetui.queue.worker_process import WorkerOptions, configure_logging

    monkeypatch.setenv("XDG_STATE_HOME", str(tmp_path / "state"))
    monkeypatch.setattr(pool_module, "worker_main", dies_at_once)
    log = tmp_path / "pool.log"
    configure_logging(str(log))
    try:
        opts = WorkerOptions(db_url=store_url, log_path=str(log))
        status = pool_module.Pool(opts, 1).run()
    finally:
        logging.getLogger("slopetui").handlers.clear()
    text = log.read_text()
    assert status == 1, text
    limit = pool_module.MAX_DEATHS_PER_WORKER
    assert text.count("died (exit code 3)") == limit + 1  # one more than the limit
    assert f"giving up: more than {limit} workers died within 60 s" in text
    assert "exits with status 1" in text
