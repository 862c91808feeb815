"""The worker pool as real processes: kill -9 mid-batch, two pools and a reader on one
SQLite file. Every job finishes exactly once. The helpers here serve the other pool
tests too (tests/test_worker_*.py)."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import threading
import time
from collections import Counter
from dataclasses import dataclass
from pathlib import Path

from sqlalchemy import func, select

from slopetui.store import Database, Run
from slopetui.store.models import Worker
from slopetui.sweeps.progress import sweep_progress
from tests.conftest import submit_quick

#: RK4 to t_end = 5e4: about 0.2 s a run here, long enough to be caught in the kernel.
MEDIUM = {"t_end": 5e4}
#: RK4 to t_end = 2e6: about 7 s a run, it cannot finish during a test's few signals.
LONG = {"t_end": 2e6}
DONE_LINE = re.compile(r"run (\d+) done")
PROGRESS_LINE = re.compile(r"\d+/\d+ runs done")


def pool_env(log: Path) -> dict[str, str]:
    """Pool files (slopetui.queue.local_pool) go beside the test's log, not in ~/.local."""
    return {**os.environ, "XDG_STATE_HOME": str(log.parent / "state")}


def start_pool(url: str, log: Path, *extra: str, group: bool = False) -> subprocess.Popen[str]:
    """A foreground `slopetui worker`; ``group``: in its own process group (and session),
    so that a signal to the group reaches the pool and its workers only."""
    return subprocess.Popen(
        [sys.executable, "-m", "slopetui", "worker", "--db", url, "--log", str(log),
         "--heartbeat", "0.5", "--lease", "3", *extra],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=pool_env(log),
        start_new_session=group)


def by_status(db: Database) -> dict[str, int]:
    with db.sessions() as s:
        return dict(s.execute(select(Run.status, func.count()).group_by(Run.status)).all())


def wait_until(what: str, check, timeout: float = 60.0):
    """Poll ``check()`` until it returns something true; return it."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        found = check()
        if found:
            return found
        time.sleep(0.03)
    raise AssertionError(f"timed out waiting for {what}")


def started_run(db: Database) -> Run | None:
    """A run in a kernel (running and charged), if any."""
    with db.sessions() as s:
        return s.scalars(select(Run).where(Run.status == "running",
                                           Run.started_at.is_not(None))).first()


def live_worker_rows(db: Database) -> list[Worker]:
    with db.sessions() as s:
        return list(s.scalars(select(Worker).where(Worker.stopped_at.is_(None))
                              .order_by(Worker.started_at)))


def pid_of(worker_id: str) -> int:
    return int(worker_id.rsplit(":", 1)[1])


def gone(pid: int) -> bool:
    """The process has exited (a zombie counts as gone)."""
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except (OSError, IndexError):
        return True
    return state == "Z"


def done_lines(*logs: Path) -> Counter[int]:
    return Counter(int(m.group(1)) for log in logs for m in DONE_LINE.finditer(log.read_text()))


@dataclass
class Frozen:
    """A worker stopped (SIGSTOP) in the middle of a batch, and what it held then."""

    worker_id: str
    done: set[int]       # runs it had finished and written
    computing: int       # the run in its kernel
    waiting: set[int]    # runs it held, not started


def freeze_mid_batch(db: Database, min_done: int, timeout: float = 60.0) -> Frozen:
    """SIGSTOP a worker once it has written ``min_done`` runs of its batch and is computing
    the next; read what it holds while it cannot change anything."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        run = started_run(db)
        if run is not None:
            with db.sessions() as s:
                n_done = s.scalar(select(func.count()).select_from(Run).where(
                    Run.worker_id == run.worker_id, Run.status == "done"))
            if n_done >= min_done:
                os.kill(pid_of(run.worker_id), signal.SIGSTOP)
                with db.sessions() as s:
                    mine = list(s.scalars(select(Run).where(Run.worker_id == run.worker_id)))
                computing = [r.id for r in mine if r.status == "running" and r.started_at]
                if computing:  # not caught between two runs
                    return Frozen(run.worker_id, {r.id for r in mine if r.status == "done"},
                                  computing[0], {r.id for r in mine if r.status == "running"
                                                 and r.started_at is None})
                os.kill(pid_of(run.worker_id), signal.SIGCONT)
        time.sleep(0.02)
    raise AssertionError("no worker was seen with finished runs written while it still "
                         "computed its batch (results written only at the end of a batch?)")


def test_kill_9_mid_batch_keeps_the_finished_runs_and_charges_only_the_run_in_the_kernel(
        tmp_path, db, db_url):
    """One worker computes 8 RK4 runs (asked for batches of 8); it is killed after writing
    two of them. Guaranteed: the runs it wrote stay done (written once, by it); the run in
    its kernel is charged for the lost attempt; it held no other run (RK4 is computed run
    by run, so it claims one at a time), and the rest were never charged: after the queue
    drains they have used one attempt each."""
    sub = submit_quick(db, 8, **MEDIUM)
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
    assert f"worker {frozen.worker_id} died (exit code -9): 1 runs requeued" in text
    # the foreground pool shows progress on stderr, as plain lines fit for a log
    assert PROGRESS_LINE.search(err) and "\r" not in err, err


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
    pools = [start_pool(db_url, log, "-j", "1", "--exit-when-idle", "--another-pool")
             for log in logs]
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
