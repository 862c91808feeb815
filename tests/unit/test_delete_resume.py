"""Resume undoes a cancel (the cancelled runs go back to the queue, an adaptive sweep goes
on refining), delete removes a sweep and its runs without leaving a reference to them
(and refuses while runs of it are running), and the command line asks before deleting.
The store tests run on SQLite and PostgreSQL (``store``); the CLI ones on SQLite."""

from __future__ import annotations

import io

import pytest
from sqlalchemy import func, select, update

from slopetui.cli import main
from slopetui.queue import jobs
from slopetui.store.models import Continuation, InitialState, Run, Sweep, Worker
from slopetui.sweeps import control
from slopetui.sweeps.adaptive import advance
from slopetui.sweeps.progress import sweep_progress
from slopetui.sweeps.spec import parse_spec
from slopetui.sweeps.submit import submit
from tests.support import ADAPTIVE_PLANE, claim_one, finish_all, submit_quick


def runs_of(db, sweep_id):
    """(status, attempts) of the sweep's runs, in id order."""
    with db.sessions() as s:
        return s.execute(select(Run.status, Run.attempts).where(Run.sweep_id == sweep_id)
                         .order_by(Run.id)).all()


def n_runs(db, *where):
    with db.sessions() as s:
        return s.scalar(select(func.count()).select_from(Run).where(*where))


# -- resume after cancel --


def test_resume_queues_a_cancelled_sweeps_runs_again_with_their_attempts(store):
    sweep = submit_quick(store, 4).sweep_id
    tried = claim_one(store, "w")                      # given back: queued, 1 attempt
    running = claim_one(store, "w")                    # this one is running at the cancel
    assert jobs.fail(store, tried, "w", "lease lost", max_attempts=3) == "queued"
    assert control.apply(store, "cancel", sweep) == f"sweep {sweep} cancelled: 3 queued runs cancelled"
    assert sorted(runs_of(store, sweep)) == [("cancelled", 0), ("cancelled", 0),
                                             ("cancelled", 1), ("running", 1)]
    assert control.apply(store, "resume", sweep) == \
        f"sweep {sweep} resumed: 3 cancelled runs queued again"
    # as they were when cancelled: the run that was tried keeps its attempt; the running
    # run was never cancelled and is untouched
    assert sorted(runs_of(store, sweep)) == [("queued", 0), ("queued", 0), ("queued", 1),
                                             ("running", 1)]
    assert sweep_progress(store, [sweep])[0].status == "active"
    again = claim_one(store, "w2")                     # handed out again
    assert again is not None and again.run_id != running.run_id


def test_resume_of_a_paused_or_active_sweep_says_its_status(store):
    sweep = submit_quick(store, 2).sweep_id
    control.pause(store, sweep)
    assert control.apply(store, "resume", sweep) == f"sweep {sweep} is active"
    assert control.resume(store, sweep) == control.Resumed("active", 0)
    with pytest.raises(control.UnknownSweep, match="SWEEP: no sweep with id 99"):
        control.resume(store, 99)


def test_a_cancelled_adaptive_sweep_resumed_goes_on_refining(store):
    sweep = submit(store, parse_spec(ADAPTIVE_PLANE)).sweep_id
    assert control.cancel(store, sweep) == 12           # the coarse lattice, level 0
    assert finish_all(store) == 0 and advance(store, sweep) == 0   # cancelled: no advance
    assert control.resume(store, sweep) == control.Resumed("active", 12)
    assert finish_all(store) == 12
    assert advance(store, sweep) > 0                    # level 1 queued from level 0's labels
    with store.sessions() as s:
        assert s.get(Sweep, sweep).level == 1


# -- delete --


def test_delete_keeps_other_sweeps_runs_and_nulls_every_reference(store):
    first = submit_quick(store, 3).sweep_id
    finish_all(store)
    copy = submit_quick(store, 3)                       # answered by the cache from `first`
    assert copy.n_cached == 3
    other = submit_quick(store, 2, tau=3.0).sweep_id
    with store.transaction() as s:
        a_run = s.scalar(select(Run.id).where(Run.sweep_id == first).limit(1))
        s.add(Worker(id="node1:1", host="node1", pid=1, run_id=a_run))
        s.add(InitialState(name="state:abc", source_run=a_run, tau=2.0, dt=0.01, state=b"x"))
        s.add(Continuation(param="k", start="hopf", a=0.1, b=0.2, c=0.3, d=0.0, k=4.0, v=1.0,
                           tau=2.0, delta=0.1, from_run=a_run, dt=0.01, max_points=10,
                           max_step=0.5, engine="e"))
    gone = control.delete(store, first)
    assert gone == control.Deletion(runs=3, running=0, copies_kept=3)
    with store.sessions() as s:
        assert s.get(Sweep, first) is None
        assert n_runs(store, Run.sweep_id == first) == 0
        kept = s.execute(select(Run.status, Run.regime, Run.cached_from)
                         .where(Run.sweep_id == copy.sweep_id)).all()
        assert len(kept) == 3 and all(st == "done" and regime and cached is None
                                      for st, regime, cached in kept)
        assert s.get(Worker, "node1:1").run_id is None
        assert s.get(InitialState, "state:abc").source_run is None
        assert s.scalar(select(Continuation.from_run)) is None
    assert runs_of(store, other) == [("queued", 0), ("queued", 0)]
    with pytest.raises(control.UnknownSweep):
        control.delete(store, first)


def test_delete_refuses_while_runs_are_running_and_writes_nothing(store):
    """A worker whose run row vanished could not write its result (every write is guarded
    by its lease), but its next ``begin`` would point its row at a missing run: refused.
    A batch claimed but not started (started_at NULL) holds its runs just the same."""
    sweep = submit_quick(store, 3).sweep_id
    batch = jobs.claim_batch(store, "w", 2)
    assert len(batch) == 2 and not any(job.started for job in batch)
    with pytest.raises(control.SweepBusy, match="while 2 of its runs are running: cancel"):
        control.apply(store, "delete", sweep)
    assert n_runs(store, Run.sweep_id == sweep) == 3
    assert jobs.begin(store, batch, "w")                # the worker carries on as before
    for job in batch:
        jobs.release(store, job, "w")
    assert control.apply(store, "delete", sweep) == f"sweep {sweep} deleted with its 3 runs"
    assert n_runs(store) == 0


def test_delete_of_a_cancelled_sweep_with_running_runs_says_to_wait(store):
    """Cancelling again would change nothing: the runs a worker holds finish or give up on
    their own. The message said "cancel it" all the same."""
    sweep = submit_quick(store, 3).sweep_id
    batch = jobs.claim_batch(store, "w", 2)
    assert control.cancel(store, sweep) == 1
    with pytest.raises(control.SweepBusy) as busy:
        control.apply(store, "delete", sweep)
    text = str(busy.value)
    assert "cancel it" not in text and "slopetui cancel" not in text
    assert "while 2 of its runs are running: the sweep is cancelled" in text
    assert "wait for them to finish or give up" in text
    assert f"slopetui runs --sweep {sweep} --status running" in text
    for job in batch:
        jobs.release(store, job, "w")
    assert control.apply(store, "delete", sweep) == f"sweep {sweep} deleted with its 3 runs"


# -- the command line --


def cli(capsys, *args):
    code = main(list(args))
    out, err = capsys.readouterr()
    return code, out, err


class Terminal(io.StringIO):
    """A stdin that says it is a terminal."""

    def isatty(self) -> bool:
        return True


def test_delete_without_yes_off_a_terminal_refuses_and_writes_nothing(db, db_url, capsys):
    sweep = submit_quick(db, 3).sweep_id
    code, out, err = cli(capsys, "delete", str(sweep), "--db", db_url)  # pytest: no tty
    assert code == 2 and out == ""
    assert "stdin is not a terminal" in err and "--yes" in err
    assert n_runs(db, Run.sweep_id == sweep) == 3
    code, out, _ = cli(capsys, "delete", str(sweep), "--yes", "--db", db_url)
    assert (code, out) == (0, f"sweep {sweep} deleted with its 3 runs\n")
    assert n_runs(db) == 0


def test_delete_asks_on_a_terminal(db, db_url, capsys, monkeypatch):
    sweep = submit_quick(db, 3).sweep_id
    asked: list[str] = []
    monkeypatch.setattr("sys.stdin", Terminal())
    for answer, code, left in (("n", 1, 3), ("", 1, 3), ("y", 0, 0)):
        monkeypatch.setattr("builtins.input", lambda q, a=answer: (asked.append(q), a)[1])
        assert cli(capsys, "delete", str(sweep), "--db", db_url)[0] == code
        assert n_runs(db, Run.sweep_id == sweep) == left
    assert len(asked) == 3
    assert asked[0].startswith(f"delete sweep {sweep} '") and asked[0].endswith(
        "' and its 3 runs? [y/N] ")


def test_delete_an_unknown_or_busy_sweep(db, db_url, capsys):
    code, _, err = cli(capsys, "delete", "99", "--yes", "--db", db_url)
    assert code == 2 and "SWEEP: no sweep with id 99" in err
    code, _, err = cli(capsys, "delete", "0", "--yes", "--db", db_url)
    assert code == 2 and "SWEEP" in err
    sweep = submit_quick(db, 2).sweep_id
    claim_one(db, "w")
    code, _, err = cli(capsys, "delete", str(sweep), "--yes", "--db", db_url)
    assert code == 2 and "running" in err and f"slopetui cancel {sweep}" in err
    assert n_runs(db, Run.sweep_id == sweep) == 2
    control.cancel(db, sweep)  # its held run finishes on its own: wait, not cancel
    code, _, err = cli(capsys, "delete", str(sweep), "--yes", "--db", db_url)
    assert code == 2 and "cancelled" in err and "wait for it to finish" in err
    assert "slopetui cancel" not in err


def test_cli_resume_of_a_cancelled_sweep(db, db_url, capsys):
    sweep = submit_quick(db, 3).sweep_id
    cli(capsys, "cancel", str(sweep), "--db", db_url)
    code, out, _ = cli(capsys, "resume", str(sweep), "--db", db_url)
    assert (code, out) == (0, f"sweep {sweep} resumed: 3 cancelled runs queued again\n")
    assert runs_of(db, sweep) == [("queued", 0)] * 3


def test_status_counts_done_only_and_shows_failed_and_cancelled(db, db_url, capsys):
    failing = submit_quick(db, 2).sweep_id
    with db.transaction() as s:  # both runs failed for good
        s.execute(update(Run).where(Run.sweep_id == failing).values(status="failed"))
    cancelled = submit_quick(db, 4, tau=3.0).sweep_id
    control.cancel(db, cancelled)
    code, out, _ = cli(capsys, "status", "--all", "--db", db_url)
    assert code == 0
    lines = out.splitlines()
    header = lines[0].split()
    assert header[4:7] == ["%", "run", "fail"] and header[7] == "canc"
    rows = {int(line.split()[0]): line.split() for line in lines[1:3]}
    # id, status, axes, done/total, %, run, fail, canc
    assert rows[failing][1] == "failed" and rows[failing][3:8] == ["0/2", "0", "0", "2", "0"]
    assert rows[cancelled][1] == "cancelled" and rows[cancelled][3:8] == ["0/4", "0", "0",
                                                                          "0", "4"]
