"""A worker's lower priority (defaults.WORKER_NICE), for every thread of its process.

On Linux a niceness belongs to a thread: nice(2) changes the calling thread's, and a thread
started before it keeps its own (a spawned worker already has one besides the main
thread when it starts: tests/integration/test_worker_nice.py saw it at nice 0). So each
thread's niceness is set by its id from /proc/self/task; threads started later inherit the
main thread's. Elsewhere os.nice is the process's.
"""

from __future__ import annotations

import os
from pathlib import Path


def lower_priority(increment: int) -> None:
    """Add ``increment`` to the niceness of every thread of this process (best effort: a
    thread that has just ended is skipped)."""
    tasks = Path("/proc/self/task")
    if not tasks.is_dir():
        os.nice(increment)
        return
    for task in tasks.iterdir():
        tid = int(task.name)
        try:
            os.setpriority(os.PRIO_PROCESS, tid, os.getpriority(os.PRIO_PROCESS, tid) + increment)
        except ProcessLookupError:
            continue
