"""One line per worker for `status` and `workers`: `workers` used to call a worker on a
continuation or a hysteresis sweep idle, and each command spelled the line its own way."""

from __future__ import annotations

from datetime import UTC, datetime

from slopetui.cli.worker_lines import worker_line
from slopetui.queue.workers_table import WorkerInfo


def _worker(wid: str, run_id: int | None = None, age: float = 3.4) -> WorkerInfo:
    return WorkerInfo(wid, "host", 1, datetime.now(UTC), age, run_id, 7)


def test_what_each_worker_computes():
    branches, hysteresis = {"w2": 5}, {"w3": 9}
    lines = [worker_line(_worker(w, r), {"branch": branches, "hysteresis": hysteresis})
             for w, r in (("w1", 12), ("w2", None), ("w3", None), ("w4", None))]
    assert [line.split()[2:4] for line in lines] == [
        ["run", "12"], ["branch", "5"], ["hysteresis", "9"], ["idle", "7"]]
    assert lines[0].endswith("7 done  heartbeat 3 s ago")


def test_an_old_heartbeat_in_minutes_and_the_id_escaped():
    line = worker_line(_worker("w\x1b[2J", age=600.0), {})
    assert "\x1b" not in line and "heartbeat 10 min ago" in line
