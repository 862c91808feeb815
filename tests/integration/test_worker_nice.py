"""Workers run at a lower priority than the pool (and the researcher's terminal), their
threads included (slopetui.queue.defaults.WORKER_NICE)."""

from __future__ import annotations

import os
import time
from pathlib import Path

from sqlalchemy import select

from slopetui.queue.defaults import WORKER_NICE
from slopetui.store.models import Worker
from tests.integration.pool_support import LONG, pid_of, start_pool, wait_until
from tests.support import submit_quick


def thread_nices(pid: int) -> dict[str, int]:
    """The niceness of every thread of a process (field 19 of each task's stat), by
    thread name and id."""
    nices = {}
    for task in Path(f"/proc/{pid}/task").iterdir():
        stat = (task / "stat").read_text()
        name = stat[stat.index("(") + 1:stat.rindex(")")]
        nices[f"{name} {task.name}"] = int(stat.rsplit(")", 1)[1].split()[16])
    return nices


def test_workers_and_their_threads_are_nice(tmp_path, db, db_url) -> None:
    submit_quick(db, 2, **LONG)
    pool = start_pool(db_url, tmp_path / "pool.log", "-j", "1")
    try:
        def computing() -> str | None:
            with db.sessions() as s:
                return s.scalar(select(Worker.id).where(Worker.run_id.is_not(None)))
        worker = wait_until("a worker computing a run", computing, 120)
        # the compute thread starts at the executor's first submit, just after the worker
        # row names its run: a loaded machine showed the main thread alone in between
        nices = wait_until("the compute thread and the main thread",
                           lambda: n if len(n := thread_nices(pid_of(worker))) >= 2 else None,
                           30)
        assert set(nices.values()) == {os.getpriority(os.PRIO_PROCESS, 0) + WORKER_NICE}, nices
        assert os.getpriority(os.PRIO_PROCESS, pool.pid) == os.getpriority(os.PRIO_PROCESS, 0)
    finally:
        pool.terminate()  # twice: the second gives the running runs back at once
        time.sleep(0.3)  # two signals back to back may merge into one: the pool would then
        pool.terminate()  # wait for the LONG run (seen: 21.6 s for this test, 2.4 s alone)
        pool.communicate(timeout=60)
