"""A pool's exit status after a stop stays 0 whatever signals follow it: a second SIGTERM
that landed after "pool stopped" (systemd's stop of the whole group, `worker --stop
--now`'s second signal) killed the process with 143 on its way out."""

from __future__ import annotations

import os
import signal
import time

from tests.integration.pool_support import start_pool, wait_until


def test_sigterms_until_the_pool_has_exited_leave_its_status_0(db_url, tmp_path):
    log = tmp_path / "pool.log"
    pool = start_pool(db_url, log, "-j", "1")
    try:
        wait_until("the worker", lambda: log.exists() and " started" in log.read_text()
                   and "worker " in log.read_text(), 120)
        # SIGTERM every millisecond from the first (a stop, then an abort) until the
        # process has exited: some land after the pool stopped, while it exits
        while pool.poll() is None:
            try:
                os.kill(pool.pid, signal.SIGTERM)
            except ProcessLookupError:
                break
            time.sleep(0.001)
        _, err = pool.communicate(timeout=60)
    finally:
        if pool.poll() is None:
            pool.kill()
            pool.communicate()
    assert pool.returncode == 0, err
    assert "pool stopped" in log.read_text()
