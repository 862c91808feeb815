"""Row locks taken in one order (runs, then the worker's row) by every statement of a
claimed run's life: a heartbeat that took the worker's row first deadlocked with a write
of the same worker on another connection (PostgreSQL's DeadlockDetected on "runs"; found
when the pool tests ran on PostgreSQL). Here a heartbeat thread and a claim/begin/complete
thread of one worker hammer one database at once."""

from __future__ import annotations

import threading

from core.point import run_point
from slopetui.queue import jobs, registry
from slopetui.store.open import open_store
from slopetui.store.workers import register_worker
from tests.support import submit_quick


def test_heartbeats_and_writes_of_one_worker_never_deadlock(pg_server):
    with pg_server.database() as url:
        db = open_store(url)
        submit_quick(db, 300, method="euler", dt=1e-3)
        register_worker(db, "w", "h", 1)
        errors: list[BaseException] = []
        done = threading.Event()

        def beat() -> None:
            try:
                while not done.is_set():
                    registry.heartbeat(db, "w")
            except BaseException as exc:
                errors.append(exc)

        first = jobs.claim_batch(db, "w", 1, {"euler"})
        record = run_point(first[0].params, first[0].settings).as_record()  # any result
        jobs.release(db, first[0], "w")
        thread = threading.Thread(target=beat)
        thread.start()
        try:
            while not errors and (batch := jobs.claim_batch(db, "w", 4, {"euler"})):
                for job in jobs.begin(db, batch, "w"):
                    jobs.complete(db, job, "w", record)
        finally:
            done.set()
            thread.join()
        assert not errors, errors[0]
        db.dispose()
