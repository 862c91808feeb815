"""The worker pools of a store on this host: start one detached, find the running ones.

A pool is found two ways, so that ``slopetui workers`` and ``slopetui worker --stop`` work
from any login (SSH included) without hunting pids in a log:

* **its pool file**, ``<user state dir>/pools/<store key>-<pid>.json``, written when the
  pool starts (by ``start_detached_pool`` at once, then by the pool itself) and removed
  when it exits. It finds a pool that has no worker registered yet (warming up). A file
  left by a killed pool is recognised (no such process, or a pid reused by another
  process: the process start time differs) and removed.
* **the workers table**: a live worker on this host is a child of its pool, so the pool's
  pid is the worker's parent pid (``/proc/PID/stat``, Linux). This also finds the pools
  of other users, or started before pool files existed.

Pools on other hosts are known only through their workers' rows (host, pids): a pool's
pid is not in the database, and a process of another host cannot be signalled from here.

The store's URL reaches a detached pool in its environment ($SLOPETUI_DB, which every
command reads when no ``--db`` is given), never in its arguments: a process's command line
(/proc/PID/cmdline, ``ps -eo args``) is readable by every user of the machine, its
environment (/proc/PID/environ) only by the same user and root, and the URL may hold the
database's password. The pool hands it on to its spawned workers inside WorkerOptions,
over multiprocessing's pipe, not on their command lines either.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import os
import signal
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

from platformdirs import user_log_path, user_state_path

from slopetui.store.location import DB_ENV

if TYPE_CHECKING:  # the modules below import sqlalchemy; callers of default_jobs need not
    from slopetui.queue.workers_table import WorkerInfo
    from slopetui.store.database import Database


def default_jobs() -> int:
    """The cores this process may use."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def default_log() -> Path:
    return user_log_path("slopetui") / "worker.log"


def open_private_log(path: Path) -> int:
    """Open the log for appending, creating it readable by its owner only (runs' errors and
    the store's URL, its password hidden, end up in it); an existing log keeps its
    permissions. Returns an fd."""
    path.parent.mkdir(parents=True, exist_ok=True, mode=0o700)
    return os.open(path, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o600)


def local_workers(db: Database) -> list[WorkerInfo]:
    """Live workers on this host."""
    from slopetui.queue.workers_table import live_workers
    host = socket.gethostname()
    return [w for w in live_workers(db) if w.host == host]


# --- processes, from /proc (Linux); elsewhere only the pool files' pids are known ---------

def _stat_fields(pid: int) -> list[str] | None:
    """The fields of /proc/PID/stat after the command name, or None."""
    try:
        text = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    return text[text.rfind(")") + 2:].split()  # the name may hold spaces and parentheses


def process_state(pid: int) -> str | None:
    """R, S, D, Z (exited, not reaped; also a thread-group leader that exited while other
    threads of it still run)..., or None if unknown (no such process, or no /proc)."""
    fields = _stat_fields(pid)
    return fields[0] if fields else None


def parent_pid(pid: int) -> int | None:
    fields = _stat_fields(pid)
    return int(fields[1]) if fields else None


def start_ticks(pid: int) -> int | None:
    """When the process started (clock ticks after boot): tells a reused pid apart."""
    fields = _stat_fields(pid)
    return int(fields[19]) if fields else None


def uptime_s(pid: int) -> float | None:
    """Seconds since the process started, or None if unknown."""
    ticks = start_ticks(pid)
    try:
        boot_s = float(Path("/proc/uptime").read_text().split()[0])
    except (OSError, ValueError, IndexError):
        return None
    return None if ticks is None else boot_s - ticks / os.sysconf("SC_CLK_TCK")


def is_alive(pid: int) -> bool:
    """The process exists and has not exited (a zombie, not yet reaped, has)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's process
        pass
    return process_state(pid) not in ("Z", "X")


def _command_line(pid: int) -> str:
    try:
        return Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode(
            errors="replace")
    except OSError:
        return ""


# --- pool files ---------------------------------------------------------------------------

def pools_dir() -> Path:
    return user_state_path("slopetui") / "pools"


def store_key(url: str) -> str:
    """The store's name in pool files: a hash of its URL as Database normalised it (the
    password is in it, so the URL itself is not written)."""
    return hashlib.sha256(url.encode()).hexdigest()[:16]


def _pool_file(url: str, pid: int) -> Path:
    return pools_dir() / f"{store_key(url)}-{pid}.json"


def write_pool_file(url: str, pid: int, log: str | None) -> Path:
    """Record a pool of the store at ``url`` (0600 in a 0700 folder)."""
    path = _pool_file(url, pid)
    path.parent.mkdir(parents=True, exist_ok=True, mode=0o700)
    record = {"pid": pid, "host": socket.gethostname(), "ticks": start_ticks(pid),
              "started": time.time(), "log": log}
    tmp = path.with_suffix(f".tmp{os.getpid()}")
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
    with os.fdopen(fd, "w", encoding="utf-8") as out:
        json.dump(record, out)
    os.replace(tmp, path)  # a reader never sees half a file
    return path


def remove_pool_file(url: str, pid: int) -> None:
    with contextlib.suppress(FileNotFoundError):
        _pool_file(url, pid).unlink()


@dataclass
class LocalPool:
    """A pool of the store on this host."""

    pid: int
    started: float | None = None    # wall time, from the pool file
    log: str | None = None
    workers: list[WorkerInfo] = field(default_factory=list)

    @property
    def uptime_s(self) -> float | None:
        up = uptime_s(self.pid)
        if up is None and self.started is not None:
            up = time.time() - self.started
        return up


def _recorded_pools(url: str) -> dict[int, LocalPool]:
    """The pools with a pool file that are still running; stale files are removed."""
    found: dict[int, LocalPool] = {}
    for path in pools_dir().glob(f"{store_key(url)}-*.json"):
        try:
            record = json.loads(path.read_text())
            pid = int(record["pid"])
        except (OSError, ValueError, KeyError, TypeError):
            continue  # being written, or not ours
        ticks = record.get("ticks")
        if is_alive(pid) and (ticks is None or start_ticks(pid) in (None, ticks)):
            found[pid] = LocalPool(pid, record.get("started"), record.get("log"))
        else:  # the pool was killed (kill -9, a reboot): its file stayed behind
            with contextlib.suppress(FileNotFoundError):
                path.unlink()
    return found


def _looks_like_a_pool(pid: int) -> bool:
    """A worker's parent is its pool, unless the worker was orphaned (re-parented to init
    or to a subreaper such as systemd --user, which is not a Python process)."""
    if pid <= 1 or not is_alive(pid):
        return False
    command = _command_line(pid)
    return not command or "python" in command or "slopetui" in command


def local_pools(db: Database) -> tuple[list[LocalPool], list[WorkerInfo]]:
    """The pools of the store on this host, with their live workers, and the live workers
    on this host whose pool is gone (orphans)."""
    url = db.url.render_as_string(hide_password=False)
    pools = _recorded_pools(url)
    orphans: list[WorkerInfo] = []
    for worker in local_workers(db):
        ppid = parent_pid(worker.pid)
        if ppid is None:  # no /proc (not Linux), or the worker just exited
            if not is_alive(worker.pid):
                continue
            orphans.append(worker)
        elif ppid in pools or _looks_like_a_pool(ppid):
            pools.setdefault(ppid, LocalPool(ppid)).workers.append(worker)
        else:
            orphans.append(worker)
    return sorted(pools.values(), key=lambda p: p.pid), orphans


# --- starting and signalling --------------------------------------------------------------

class PoolRunning(Exception):
    """A pool of this store already runs on this host (and a second one was not asked for)."""

    def __init__(self, pools: list[LocalPool]) -> None:
        self.pools = pools
        pids = ", ".join(str(p.pid) for p in pools)
        super().__init__(f"a worker pool of this store already runs on this host (pid "
                         f"{pids}); stop it with `slopetui worker --stop`")


@contextlib.contextmanager
def _store_lock(url: str) -> Iterator[None]:
    """Serialise the check-then-start of two `worker --detach` run at the same moment."""
    path = pools_dir() / f"{store_key(url)}.lock"
    path.parent.mkdir(parents=True, exist_ok=True, mode=0o700)
    fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o600)
    try:
        try:
            import fcntl
        except ImportError:  # not POSIX: no lock, the check still runs
            yield
            return
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)


def pool_environment(url: str) -> dict[str, str]:
    """The environment of a pool started from here: this process's, with the store's URL
    (password included) in $SLOPETUI_DB, where ``slopetui worker`` without ``--db`` reads
    it. Readable by this user and root only, unlike a command line (module docstring)."""
    return {**os.environ, DB_ENV: url}


def start_detached_pool(db: Database, *, jobs: int | None = None, log: Path | None = None,
                        extra: tuple[str, ...] = (), another_pool: bool = False
                        ) -> tuple[int, Path]:
    """``slopetui worker`` in a new session (it survives the terminal and the SSH
    session), the store's URL in its environment, not its arguments (pool_environment);
    ``extra``: more of its options. Returns its pid and log file. Raises PoolRunning if a
    pool of the store runs on this host already, unless ``another_pool``."""
    log = log or default_log()
    url = db.url.render_as_string(hide_password=False)
    # no --db: the URL goes in the environment (see the module docstring)
    cmd = [sys.executable, "-m", "slopetui", "worker", "--log", str(log),
           "--another-pool", *extra]  # checked here, under the lock
    if jobs is not None:
        cmd += ["-j", str(jobs)]
    with _store_lock(url):
        if not another_pool:
            pools, _ = local_pools(db)
            if pools:
                raise PoolRunning(pools)
        fd = open_private_log(log)
        try:
            proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=fd, stderr=fd,
                                    start_new_session=True, close_fds=True,
                                    env=pool_environment(url))
        finally:
            os.close(fd)
        # Recorded before the lock is released, so a second --detach sees this pool even
        # while it is still starting; the pool rewrites the same file when it is up.
        write_pool_file(url, proc.pid, str(log))
    return proc.pid, log


def signal_pool(pid: int, *, now: bool = False) -> None:
    """Ask a pool to stop: SIGTERM (its running jobs finish). ``now``: a second SIGTERM
    (they go back to the queue at once). The pool counts every signal it receives, but two
    signals sent back to back may merge into one, so the second waits a moment."""
    os.kill(pid, signal.SIGTERM)
    if now:
        time.sleep(0.3)
        os.kill(pid, signal.SIGTERM)
