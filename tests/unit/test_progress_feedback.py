"""What the faces say of a sweep's pace and of the runs workers hold: a finished sweep's
final rate (not one that decays to 0 as its runs leave the recent window), and runs
claimed in a batch but not begun said as such, not as "running"."""

from __future__ import annotations

from datetime import timedelta

import pytest
from sqlalchemy import update

from slopetui.cli import main
from slopetui.queue import jobs
from slopetui.store.models import Run
from slopetui.store.queries import database_now
from slopetui.store.sweeps.progress import running_runs
from slopetui.sweeps import control
from slopetui.sweeps.progress import RATE_WINDOW_MIN, claimed_line, claimed_text, sweep_progress
from tests.support import finish_all, submit_quick


def set_times(db, sweep_id, minutes_ago):
    """Give the sweep's runs, in id order, these (start, finish) times, minutes before now."""
    now = database_now(db)
    with db.transaction() as s:
        ids = s.scalars(Run.__table__.select().with_only_columns(Run.id)
                        .where(Run.sweep_id == sweep_id).order_by(Run.id)).all()
        for rid, (start, finish) in zip(ids, minutes_ago, strict=True):
            s.execute(update(Run).where(Run.id == rid).values(
                started_at=now - timedelta(minutes=start),
                finished_at=now - timedelta(minutes=finish)))


def one(db, sweep_id):
    return sweep_progress(db, [sweep_id])[0]


@pytest.mark.parametrize("ago", [0.0, 30.0])  # its last run just finished; half an hour ago
def test_a_finished_sweep_shows_its_final_rate(store, ago):
    """3 runs from the first start to the last finish in 2 minutes: 1.5 runs/min, however
    long ago; the recent window's rate (read before) fell to 0 once they left it, and
    decayed before that."""
    sweep = submit_quick(store, 3).sweep_id
    assert finish_all(store) == 3
    set_times(store, sweep, [(ago + 2.0, ago + 1.5), (ago + 1.5, ago + 1.0), (ago + 1.0, ago)])
    p = one(store, sweep)
    assert p.status == "done" and p.rate_final
    assert p.runs_per_min == pytest.approx(1.5, rel=1e-3)
    # the pool's throughput stays the recent one
    assert p.recent_per_min == (0.0 if ago > RATE_WINDOW_MIN else pytest.approx(1.5, rel=1e-2))


def test_an_active_sweep_shows_its_recent_rate_and_a_cancelled_idle_one_its_final(store):
    sweep = submit_quick(store, 4).sweep_id
    claimed = jobs.begin(store, jobs.claim_batch(store, "w", 2), "w")
    for job in claimed:
        jobs.complete(store, job, "w", {**_record(job)})
    set_times(store, sweep, [(40.0, 39.0), (39.0, 38.0), (0.0, 0.0), (0.0, 0.0)])
    p = one(store, sweep)
    assert p.status == "active" and not p.rate_final and p.runs_per_min == 0.0
    control.cancel(store, sweep)
    p = one(store, sweep)
    assert p.status == "cancelled" and p.rate_final
    assert p.runs_per_min == pytest.approx(1.0, rel=1e-3)  # 2 runs from 40 to 38 min ago


def _record(job):
    from core.point import run_point

    return run_point(job.params, job.settings, job.carried).as_record()


def test_claimed_text_says_what_the_held_runs_are():
    assert claimed_text(0, 0, 2) == ""
    assert claimed_text(39, 8, 2) == ("39 runs claimed in batches on 2 workers (8 computing, "
                                      "31 waiting their turn)")
    assert claimed_text(2, 2, 2) == "2 runs computing on 2 workers"
    assert claimed_text(1, 1, 1) == "1 run computing on 1 worker"
    assert claimed_text(3, 0, 0).startswith("3 runs held by no live worker: queued again")


def test_the_store_counts_held_and_begun_runs(store):
    submit_quick(store, 5)
    assert running_runs(store) == (0, 0)
    batch = jobs.claim_batch(store, "w", 4)
    assert running_runs(store) == (4, 0)
    jobs.begin(store, batch[:1], "w")
    assert running_runs(store) == (4, 1)
    assert claimed_line(store, 2) == ("4 runs claimed in batches on 2 workers (1 computing, "
                                      "3 waiting their turn)")


def test_status_says_runs_claimed_in_batches(db, db_url, capsys):
    submit_quick(db, 5)
    jobs.claim_batch(db, "w", 4)
    assert main(["status", "--db", db_url]) == 0
    out = capsys.readouterr().out
    assert "4 runs held by no live worker" in out

