"""A hysteresis sweep computed by real `slopetui worker` pools, killed on the way: a worker
killed with SIGKILL mid-sweep, then the whole pool stopped with SIGTERM between two
points; the sweep resumes each time from its saved points and is finished exactly once,
with every point saved once and in order (up, then down)."""

from __future__ import annotations

import numpy as np

from core.params import Params
from slopetui.queue import hysteresis_jobs
from slopetui.queue.hysteresis_jobs import HysteresisSpec
from slopetui.store.jobs import hysteresis_sweeps
from tests.integration.pool_support import interrupt_twice_then_finish

#: 0.04-0.1 s a point at tau = 2 with t_settle = 3000; the two interruptions take about
#: ten points (measured: the worker killed after 6 points were saved, the pool stopped
#: after 10, 80 points then took 4 s more to finish): 30 points leave twenty to spare.
SPEC = HysteresisSpec(Params(tau=2.0), "k", 8.0, 12.0, 15, 0.01, 3000.0, 100.0)
TOTAL = 2 * SPEC.n_points


def _row(db):
    return hysteresis_sweeps.hysteresis_sweep(db, 1)


def test_a_sweep_survives_kill_9_and_a_stop_and_finishes_once(tmp_path, db, db_url):
    sid = hysteresis_jobs.submit(db, SPEC)
    log = tmp_path / "pool.log"
    err = interrupt_twice_then_finish(db_url, log, lambda: _row(db), "n_done", TOTAL)
    done = _row(db)
    assert done.status == "done" and done.n_done == TOTAL
    assert done.attempts == 2  # the kill cost an attempt; the stop gave its attempt back
    points = hysteresis_sweeps.points(db, sid)
    assert [p.idx for p in points] == list(range(TOTAL))
    values = SPEC.values()
    assert [p.direction for p in points] == ["up"] * SPEC.n_points + ["down"] * SPEC.n_points
    assert [p.value for p in points] == [*values, *values[::-1]]
    # refined inside the grid's bracket, whose ends are grid values
    assert np.isin([done.onset_up_before, done.onset_up_after], values).all()
    assert done.onset_up_before < done.onset_up < done.onset_up_after
    text = log.read_text()
    assert text.count(f"hysteresis sweep {sid} done") == 1
    assert "died (exit code -9): 1 jobs requeued" in text
    assert text.count("resumed") == 2 and "Traceback" not in text + err
