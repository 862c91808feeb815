"""The worker pool as real processes: kill -9, two pools and a reader on one SQLite
file, graceful and immediate shutdown. Every job finishes exactly once."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import threading
import time
from collections import Counter
from pathlib import Path

from sqlalchemy import func, select

from slopetui.store import Database, Run
from slopetui.sweeps.progress import sweep_progress
from tests.conftest import submit_quick

#: RK4 with lambda_max to t_end = 2e5: about 0.7 s a run on this machine, long enough to
#: be caught in the middle.
SLOW = {"t_end": 2e5, "window": 100.0}
DONE_LINE = re.compile(r"run (\d+) done")


def start_pool(url: str, log: Path, *extra: str) -> subprocess.Popen[str]:
    return subprocess.Popen(
        [sys.executable, "-m", "slopetui", "worker", "--db", url, "--log", str(log),
         "--heartbeat", "0.5", "--lease", "3", *extra],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def by_status(db: Database) -> dict[str, int]:
    with db.sessions() as s:
        return dict(s.execute(select(Run.status, func.count()).group_by(Run.status)).all())


def wait_for_running(db: Database, timeout: float = 120) -> Run:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        with db.sessions() as s:
            run = s.scalars(select(Run).where(Run.status == "running")).first()
        if run is not None:
            return run
        time.sleep(0.05)
    raise AssertionError("no run started")


def done_lines(*logs: Path) -> Counter[int]:
    return Counter(int(m.group(1)) for log in logs for m in DONE_LINE.finditer(log.read_text()))


def test_kill_9_of_a_worker_mid_run_loses_and_duplicates_nothing(tmp_path, db, db_url):
    sub = submit_quick(db, 6, **SLOW)
    log = tmp_path / "pool.log"
    pool = start_pool(db_url, log, "-j", "2", "--exit-when-idle")
    victim = wait_for_running(db)
    time.sleep(0.2)  # well inside the run
    with db.sessions() as s:  # the victim's whole batch
        batch = set(s.scalars(select(Run.id).where(Run.worker_id == victim.worker_id,
                                                   Run.status == "running")))
    os.kill(int(victim.worker_id.rsplit(":", 1)[1]), signal.SIGKILL)
    _, err = pool.communicate(timeout=300)
    assert pool.returncode == 0, err
    assert by_status(db) == {"done": 6}
    with db.sessions() as s:
        runs = list(s.scalars(select(Run)))
    assert victim.id in batch
    for run in runs:  # the batch went back to the queue and was computed again, elsewhere
        assert run.attempts == (2 if run.id in batch else 1), run.id
        assert run.worker_id != victim.worker_id
    with db.sessions() as s:
        ids = set(s.scalars(select(Run.id).where(Run.sweep_id == sub.sweep_id)))
    assert done_lines(log) == Counter(ids)  # each run written once
    assert f"worker {victim.worker_id} died (exit code -9)" in log.read_text()


def test_two_pools_and_a_reader_on_one_file(tmp_path, db, db_url):
    n = 60
    # ~0.1 s runs: long enough that both pools are up before the queue drains, short
    # enough for many claims and writes per second
    submit_quick(db, n, t_end=3e4)
    logs = [tmp_path / "a.log", tmp_path / "b.log"]
    reads, errors = [0], []
    stop = threading.Event()

    def reader() -> None:
        other = Database(db_url)
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
    pools = [start_pool(db_url, log, "-j", "1", "--exit-when-idle") for log in logs]
    outputs = [p.communicate(timeout=300) for p in pools]
    stop.set()
    thread.join()
    assert [p.returncode for p in pools] == [0, 0], outputs
    assert errors == [] and reads[0] > 10
    assert by_status(db) == {"done": n}
    lines = done_lines(*logs)
    assert len(lines) == n and set(lines.values()) == {1}
    assert done_lines(logs[0]) and done_lines(logs[1])  # both pools did work
    text = logs[0].read_text() + logs[1].read_text() + "".join(o[1] for o in outputs)
    assert "locked" not in text and "Traceback" not in text


def test_sigterm_lets_the_running_job_finish_and_keeps_the_rest_queued(tmp_path, db, db_url):
    submit_quick(db, 4, **SLOW)
    log = tmp_path / "pool.log"
    pool = start_pool(db_url, log, "-j", "1", "--batch", "2")
    first = wait_for_running(db)
    pool.send_signal(signal.SIGTERM)
    pool.communicate(timeout=120)
    assert pool.returncode == 0
    counts = by_status(db)  # the running batch of 2 finished; the rest stayed queued
    assert "running" not in counts and counts["done"] >= 2
    assert counts["done"] + counts["queued"] == 4 and counts["queued"] >= 1
    with db.sessions() as s:
        assert s.get(Run, first.id).status == "done"
    assert sorted(done_lines(log).values()) == [1] * counts["done"]


def test_a_second_signal_gives_the_running_job_back_at_once(tmp_path, db, db_url):
    submit_quick(db, 2, t_end=2e6, window=100.0)  # ~7 s a run: it cannot finish first
    log = tmp_path / "pool.log"
    pool = start_pool(db_url, log, "-j", "1")
    running = wait_for_running(db)
    t0 = time.monotonic()
    pool.send_signal(signal.SIGINT)
    time.sleep(0.05)
    pool.send_signal(signal.SIGINT)
    pool.communicate(timeout=120)
    assert time.monotonic() - t0 < 5
    with db.sessions() as s:
        run = s.get(Run, running.id)
        # back in the queue, and the interrupted attempt is not counted against it
        assert run.status == "queued" and run.attempts == 0 and run.worker_id is None
    assert by_status(db) == {"queued": 2}
