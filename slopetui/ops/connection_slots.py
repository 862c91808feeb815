"""A budget of database connections shared by the processes of one worker pool.

PostgreSQL allows 100 connections by default, and each one is a server process. A pool of
N workers that each kept a connection (plus one for a heartbeat thread) needed 2N + 1:
16 nodes x 64 workers would need ~2,000. A worker needs its connection only for the
milliseconds of a claim or a write, between computations that take seconds; so the
pool's processes share ``count`` slots: a process holds a slot while it has a connection
open, and gives the slot back when it closes its connections before it computes or
sleeps (``Database.idle``). The pool then uses at most ``count`` connections, whatever
its number of workers.

A slot is an exclusive ``flock`` on one of ``count`` files in a folder of the pool's own
on the node's local disk. The kernel drops a process's locks when it dies, kill -9
included, so a slot is never lost with its holder. Slots are per process: the threads of
one process share its slot (a worker's main thread is the only one that uses the store).
"""

from __future__ import annotations

import fcntl
import os
import shutil
import tempfile
import threading
import time
from pathlib import Path

#: Connections a pool may hold at once by default. A worker holds one for a few ms a
#: batch (benchmarks/bench_pools.py: the queue costs a worker ~2-2.5 ms of CPU a run)
#: against batches that compute for seconds to minutes at the paper's settings; even one
#: slot kept two workers a pool busy on 2,000 runs of 6 ms
#: (tests/integration/test_many_hosts.py). Two leave room for a pool's own statements
#: (a dead worker's requeue, progress) beside a claim.
DEFAULT_CONNECTIONS = 2
#: Waiting for a slot: the first retry after this long, doubling up to WAIT_MAX_S (s).
WAIT_MIN_S, WAIT_MAX_S = 0.001, 0.05


def slots_folder(owner: str) -> Path:
    """A new private folder for a pool's slot files on this node's own disk (the temporary
    folder, not a shared home); ``owner`` names it (e.g. the pool's host and pid)."""
    base = Path(tempfile.gettempdir()) / f"slopetui-{os.getuid()}"
    base.mkdir(mode=0o700, exist_ok=True)
    return Path(tempfile.mkdtemp(prefix=f"slots-{owner}-", dir=base))


def remove_slots_folder(folder: Path) -> None:
    shutil.rmtree(folder, ignore_errors=True)


class ConnectionSlots:
    """``count`` slots in ``folder`` (see the module docstring); ``acquire`` before a
    connection opens, ``release`` after it closed."""

    def __init__(self, folder: Path, count: int) -> None:
        if count < 1:
            raise ValueError(f"ConnectionSlots.count must be >= 1, got {count}")
        self.folder, self.count = folder, count
        self._lock = threading.Lock()
        self._open = 0  # connections of this process now open
        self._fd: int | None = None

    def _take(self) -> int:
        """Lock a free slot file, waiting as long as every slot is held; its descriptor."""
        first = os.getpid() % self.count  # spread the processes over the slots
        wait = WAIT_MIN_S
        while True:
            for i in range(self.count):
                fd = os.open(self.folder / f"slot-{(first + i) % self.count}",
                             os.O_RDWR | os.O_CREAT, 0o600)
                try:
                    fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
                except BlockingIOError:
                    os.close(fd)
                    continue
                return fd
            time.sleep(wait)
            wait = min(2 * wait, WAIT_MAX_S)

    def acquire(self) -> None:
        with self._lock:
            if self._open == 0:
                self._fd = self._take()
            self._open += 1

    def release(self) -> None:
        with self._lock:
            self._open -= 1
            if self._open == 0 and self._fd is not None:
                os.close(self._fd)  # closing the file drops its lock
                self._fd = None

    @property
    def held(self) -> bool:
        return self._fd is not None
