"""Helpers for the Pilot tests of the application."""

from __future__ import annotations

import asyncio
import time
from collections.abc import Callable

from core import run_point
from slopetui.queue import jobs
from slopetui.store import Database


def finish_all(db: Database, worker: str = "test") -> int:
    """Compute every queued run in this process, as a worker would."""
    n = 0
    while (job := jobs.claim(db, worker)) is not None:
        jobs.complete(db, job, worker, run_point(job.params, job.settings).as_record())
        n += 1
    return n


async def wait_until(pilot, predicate: Callable[[], bool], timeout: float = 20.0) -> None:
    """Let the app run until predicate() holds (thread workers deliver asynchronously)."""
    deadline = time.monotonic() + timeout
    while not predicate():
        if time.monotonic() > deadline:
            raise AssertionError("the app did not reach the expected state")
        await pilot.pause(0.05)


def run(scenario) -> None:
    asyncio.run(scenario())
