"""Helpers of the worker-pool tests (test_pool.py, test_worker_*.py): real `slopetui worker`
processes, their logs, and polling the store while they run."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import time
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from sqlalchemy import func, select

from slopetui.store.database import Database
from slopetui.store.models import Run, Worker

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


def interrupt_twice_then_finish(url: str, log: Path, row: Callable[[], Any],
                                counter: str, total: int) -> str:
    """Compute the one queued point-by-point job (a continuation, a hysteresis sweep:
    ``row()`` reads it, ``counter`` is its column of saved points, ``total`` how many it
    has when done) on one-worker pools, interrupted twice: its worker killed with SIGKILL
    mid-point once 5 points are saved, then, once another worker resumed it and saved 3
    more, the pool stopped with SIGTERM between two points (the job back in the queue,
    unfinished). A last pool that exits when idle finishes it; returns its stderr."""
    pool = start_pool(url, log, "-j", "1")
    try:
        saved = wait_until("5 points saved", lambda: getattr(r := row(), counter) >= 5 and r,
                           120)
        holder = saved.worker_id
        os.kill(pid_of(holder), signal.SIGKILL)          # the worker, mid-point
        wait_until("the killed worker to be gone", lambda: gone(pid_of(holder)), 30)
        wait_until("another worker to resume it", lambda: (
            (r := row()).status == "running" and r.worker_id != holder), 60)
        wait_until("more points", lambda: getattr(row(), counter) >= getattr(saved, counter) + 3,
                   60)
        pool.send_signal(signal.SIGTERM)                # a stop: between two points
        _, err = pool.communicate(timeout=60)
    finally:
        if pool.poll() is None:
            os.killpg(pool.pid, signal.SIGKILL)
            pool.communicate()
    assert pool.returncode == 0, err
    stopped = row()
    assert stopped.status == "queued" and getattr(stopped, counter) < total
    pool = start_pool(url, log, "-j", "1", "--exit-when-idle")
    _, err = pool.communicate(timeout=300)
    assert pool.returncode == 0, err
    return err
