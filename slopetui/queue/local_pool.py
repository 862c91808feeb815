"""Start a detached worker pool on this host, or find the one already running."""

from __future__ import annotations

import socket
import subprocess
import sys
from pathlib import Path

from platformdirs import user_log_path

from slopetui.store.database import Database
from slopetui.sweeps.progress import WorkerInfo, live_workers


def default_log() -> Path:
    return user_log_path("slopetui") / "worker.log"


def local_workers(db: Database) -> list[WorkerInfo]:
    """Live workers on this host."""
    host = socket.gethostname()
    return [w for w in live_workers(db) if w.host == host]


def start_detached_pool(db: Database, *, jobs: int | None = None, log: Path | None = None,
                        extra: tuple[str, ...] = ()) -> tuple[int, Path]:
    """``slopetui worker`` in a new session (it survives the terminal and the SSH
    session); returns its pid and log file."""
    log = log or default_log()
    log.parent.mkdir(parents=True, exist_ok=True, mode=0o700)
    cmd = [sys.executable, "-m", "slopetui", "worker", "--db",
           db.url.render_as_string(hide_password=False), "--log", str(log), *extra]
    if jobs is not None:
        cmd += ["-j", str(jobs)]
    with open(log, "a", encoding="utf-8") as out:
        proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=out, stderr=out,
                                start_new_session=True, close_fds=True)
    return proc.pid, log
