"""The worker pool as real processes: kill -9 mid-batch, two pools and a reader on one
store. Every job finishes exactly once. The helpers are in pool_support.py (they serve the
other pool tests too, test_worker_*.py).

The two pools run on SQLite and PostgreSQL (``store``): concurrent claims are where the
backends differ (SKIP LOCKED; tests/integration/test_claims_postgres.py). kill -9 runs on
SQLite only, for time (on both it doubled the module's): on PostgreSQL a dead worker's
runs going back is tests/unit/test_queue.py's, and workers killed with their connections
open is tests/integration/test_many_hosts.py's."""

from __future__ import annotations

import os
import signal
import threading
from collections import Counter

from sqlalchemy import select

from slopetui.store.models import Run
from slopetui.store.open import open_store
from slopetui.sweeps.progress import sweep_progress
from tests.integration.pool_support import (
    MEDIUM,
    PROGRESS_LINE,
    by_status,
    done_lines,
    freeze_mid_batch,
    live_worker_rows,
    pid_of,
    start_pool,
    wait_until,
)
from tests.support import submit_quick


def test_kill_9_mid_batch_keeps_the_finished_runs_and_charges_only_the_run_in_the_kernel(
        tmp_path, db, db_url):
    """One worker computes 8 RK4 runs (asked for batches of 8); it is killed after writing
    two of them. Guaranteed: the runs it wrote stay done (written once, by it); the run in
    its kernel is charged for the lost attempt; it held no other run (runs of the
    consistent history are computed run by run, so it claims one at a time: the batched
    kernels start from the constant history only), and the rest were never charged: after
    the queue drains they have used one attempt each."""
    sub = submit_quick(db, 8, history="consistent", **MEDIUM)
    log = tmp_path / "pool.log"
    pool = start_pool(db_url, log, "-j", "1", "--batch", "8", "--exit-when-idle")
    frozen = freeze_mid_batch(db, min_done=2)
    os.kill(pid_of(frozen.worker_id), signal.SIGKILL)
    _, err = pool.communicate(timeout=120)
    assert pool.returncode == 0, err
    assert by_status(db) == {"done": 8}
    with db.sessions() as s:
        runs = {r.id: r for r in s.scalars(select(Run).where(Run.sweep_id == sub.sweep_id))}
    assert frozen.done and not frozen.waiting and frozen.computing not in frozen.done
    for run in runs.values():
        if run.id in frozen.done:  # written before the kill, not computed again
            assert (run.worker_id, run.attempts) == (frozen.worker_id, 1), run.id
        else:
            assert run.worker_id != frozen.worker_id
            assert run.attempts == (2 if run.id == frozen.computing else 1), run.id
    assert done_lines(log) == Counter(set(runs))  # each run written once
    text = log.read_text()
    assert f"worker {frozen.worker_id} died (exit code -9): 1 jobs requeued" in text
    # the foreground pool shows progress on stderr, as plain lines fit for a log
    assert PROGRESS_LINE.search(err) and "\r" not in err, err


def test_two_pools_and_a_reader_on_one_store(tmp_path, store, store_url):
    """Two pools (one worker each) claim from one queue at once while a third process
    reads it: every run done once, by both pools, and no error anywhere. The runs are
    queued once both pools' workers are up, so that both take part however long their
    start takes; the pools are then stopped (SIGTERM) once the queue is drained."""
    n = 30
    logs = [tmp_path / "a.log", tmp_path / "b.log"]
    reads, errors = [0], []
    stop = threading.Event()

    def reader() -> None:
        other = open_store(store_url)
        while not stop.is_set():
            try:
                sweep_progress(other)
                by_status(other)
                reads[0] += 1
            except Exception as exc:  # any error at all fails the test below
                errors.append(repr(exc))
        other.dispose()

    thread = threading.Thread(target=reader)
    thread.start()
    pools = [start_pool(store_url, log, "-j", "1", "--another-pool") for log in logs]
    try:
        wait_until("both pools' workers", lambda: len(live_worker_rows(store)) == 2, 120)
        # ~0.15 s runs: many claims and writes per second, from both pools (before, 60
        # runs of 0.2 s, so that the second pool was up before the first drained the queue)
        # claimed one at a time (not the batched kernels' constant history), so both pools
        # take part: a batch of 30 runs of one tau would go to one pool whole
        submit_quick(store, n, t_end=1e4, history="consistent")
        wait_until("the queue to drain", lambda: by_status(store) == {"done": n}, 120)
        for p in pools:
            p.send_signal(signal.SIGTERM)
        outputs = [p.communicate(timeout=60) for p in pools]
    finally:
        stop.set()
        thread.join()
        for p in pools:
            if p.poll() is None:
                p.kill()
                p.communicate()
    assert [p.returncode for p in pools] == [0, 0], outputs
    assert errors == [] and reads[0] > 10
    assert by_status(store) == {"done": n}
    lines = done_lines(*logs)
    assert len(lines) == n and set(lines.values()) == {1}
    assert done_lines(logs[0]) and done_lines(logs[1])  # both pools did work
    text = logs[0].read_text() + logs[1].read_text() + "".join(o[1] for o in outputs)
    assert "locked" not in text and "Traceback" not in text
