"""When a worker leaves on its own (slopetui.queue.idle_exit): --exit-when-idle waits out a
paused sweep for the grace period, the application's pool leaves once its owner has quit
and the store has been idle; the store's backlog behind those decisions
(slopetui.store.jobs.backlog), on SQLite and PostgreSQL (``store``)."""

from __future__ import annotations

import json
import os
import subprocess

import pytest

from slopetui.cli import main
from slopetui.queue import hysteresis_jobs
from slopetui.queue.idle_exit import IdleExit, Owner
from slopetui.queue.local_pool import start_ticks
from slopetui.queue.open_apps import open_apps, record_app
from slopetui.queue.registry import backlog
from slopetui.store.jobs.backlog import Backlog
from slopetui.sweeps import control
from tests.support import claim_one, submit_quick
from tests.unit.test_hysteresis_jobs import SPEC

DRAINED = Backlog(claimable=0, running=0, paused=0)
PAUSED = Backlog(claimable=0, running=0, paused=300)
RUNNING = Backlog(claimable=0, running=1, paused=300)


class Clock:
    def __init__(self) -> None:
        self.t = 1000.0

    def __call__(self) -> float:
        return self.t


def _look(idle: IdleExit, seen: Backlog) -> str | None:
    """One idle round of the worker's loop."""
    idle.new_round()
    return idle.reason_to_leave(lambda: seen)


def test_the_backlog_counts_paused_runs_apart_and_every_kind_of_job(store):
    sub = submit_quick(store, 3)
    assert backlog(store) == Backlog(claimable=3, running=0, paused=0)
    control.pause(store, sub.sweep_id)
    paused = backlog(store)
    assert paused == Backlog(claimable=0, running=0, paused=3)
    assert paused.idle and not paused.drained  # paused runs alone: --exit-when-idle leaves
    control.resume(store, sub.sweep_id)
    claim_one(store, "w1")
    assert backlog(store) == Backlog(claimable=2, running=1, paused=0)
    hysteresis_jobs.submit(store, SPEC)  # a queued hysteresis sweep is claimable work too
    assert backlog(store).claimable == 3


def test_a_drained_queue_is_left_at_once():
    idle = IdleExit(True, 60.0, clock=Clock())
    assert _look(idle, DRAINED) == "nothing queued or running"


def test_a_paused_sweep_keeps_the_worker_for_the_grace_period():
    clock = Clock()
    idle = IdleExit(True, 60.0, clock=clock)
    assert _look(idle, PAUSED) is None
    clock.t += 59.0
    assert _look(idle, PAUSED) is None
    clock.t += 1.0
    assert _look(idle, PAUSED) == ("nothing claimable for 60 s (300 runs queued in paused "
                                   "sweeps)")


def test_a_running_run_or_a_claim_starts_the_clock_again():
    clock = Clock()
    idle = IdleExit(True, 10.0, clock=clock)
    assert _look(idle, PAUSED) is None
    clock.t += 9.0
    assert _look(idle, RUNNING) is None  # it may come back: wait for it, however long
    clock.t += 100.0
    assert _look(idle, RUNNING) is None
    assert _look(idle, PAUSED) is None  # the clock starts now
    clock.t += 9.0
    idle.new_round()  # a round that claimed work (no look at the end of it)
    assert _look(idle, PAUSED) is None  # started again
    clock.t += 9.0
    assert _look(idle, PAUSED) is None
    clock.t += 1.0
    assert _look(idle, PAUSED) is not None


def test_a_zero_grace_leaves_at_once_as_before():
    assert _look(IdleExit(True, 0.0, clock=Clock()), PAUSED) is not None


class FakeOwner(Owner):
    def __init__(self) -> None:
        super().__init__(pid=4242, ticks=1, found=True)
        object.__setattr__(self, "alive", True)

    def gone(self) -> bool:
        return not self.alive  # type: ignore[attr-defined]


def test_the_applications_pool_stays_while_its_owner_runs_then_leaves_once_idle():
    clock = Clock()
    owner = FakeOwner()
    idle = IdleExit(False, 60.0, owner, clock=clock)

    def unread() -> Backlog:
        raise AssertionError("the store is read only once the owner is gone")
    for _ in range(3):
        clock.t += 1000.0
        idle.new_round()
        assert idle.reason_to_leave(unread) is None
    object.__setattr__(owner, "alive", False)
    assert _look(idle, RUNNING) is None       # the queue is still being worked off
    clock.t += 30.0
    assert _look(idle, DRAINED) is None       # idle now: the grace starts
    clock.t += 59.0
    assert _look(idle, DRAINED) is None
    clock.t += 1.0
    assert _look(idle, DRAINED) == ("the process that started the pool (pid 4242) and the "
                                    "applications of the store have quit, and nothing was "
                                    "claimable or running for 60 s")


def test_the_grace_counts_from_the_owners_exit():
    clock = Clock()
    owner = FakeOwner()
    idle = IdleExit(False, 60.0, owner, clock=clock)
    assert _look(idle, DRAINED) is None
    clock.t += 500.0  # idle for long while the application ran
    object.__setattr__(owner, "alive", False)
    assert _look(idle, DRAINED) is None
    clock.t += 60.0
    assert _look(idle, DRAINED) is not None


def test_an_application_opened_again_after_the_owner_quit_keeps_the_pool():
    """The owner is asked again every idle round: the application quit, was opened again
    within the grace period (it found the pool and recorded itself), and the pool stays;
    the grace counts anew from its second exit."""
    clock = Clock()
    owner = FakeOwner()
    idle = IdleExit(False, 60.0, owner, clock=clock)
    object.__setattr__(owner, "alive", False)
    assert _look(idle, DRAINED) is None
    clock.t += 30.0
    object.__setattr__(owner, "alive", True)   # another application of the store opened
    assert _look(idle, DRAINED) is None
    clock.t += 100.0
    assert _look(idle, DRAINED) is None        # open: the pool stays however long it idles
    object.__setattr__(owner, "alive", False)
    clock.t += 1.0
    assert _look(idle, DRAINED) is None
    clock.t += 59.0
    assert _look(idle, DRAINED) is None        # 59 s since that exit
    clock.t += 1.0
    assert _look(idle, DRAINED) is not None


def test_a_worker_without_exit_rules_never_leaves():
    idle = IdleExit(False, 0.0, clock=Clock())
    assert not idle.watching and _look(idle, DRAINED) is None


def test_an_owner_is_its_pid_and_its_start_time():
    proc = subprocess.Popen(["sleep", "60"])
    try:
        owner = Owner.of(proc.pid)
        assert owner.found and not owner.gone()
        # the same pid, started at another time: a reused pid, not the owner
        assert Owner(proc.pid, start_ticks(proc.pid) + 1, True).gone()
    finally:
        proc.kill()
        proc.wait()
    assert owner.gone()
    assert Owner.of(proc.pid).gone()  # gone before the pool started: gone for good


@pytest.mark.parametrize(("option", "value", "says"), [
    ("--idle-grace", "-1", "--idle-grace must be a finite number of seconds from 0 to 86400"),
    ("--idle-grace", "inf", "--idle-grace must be a finite number of seconds"),
    ("--idle-grace", "nan", "--idle-grace must be a finite number of seconds"),
    ("--owner-pid", "0", "--owner-pid must be a finite number from 1 to 4.1943e+06"),
])
def test_bad_idle_options_are_refused_in_one_line(option, value, says, tmp_path, capsys):
    url = f"sqlite:///{tmp_path / 's.db'}"
    assert main(["worker", "--exit-when-idle", option, value, "--db", url]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and says in err
    assert not (tmp_path / "s.db").exists()  # refused before the store is opened


def test_the_other_applications_of_the_store_keep_the_pool(tmp_path, monkeypatch):
    """A second application that found the pool (and did not start it) keeps it: the
    owner is gone only once every application of the store has quit."""
    monkeypatch.setenv("XDG_STATE_HOME", str(tmp_path / "state"))
    first, second = subprocess.Popen(["sleep", "60"]), subprocess.Popen(["sleep", "60"])
    try:
        owner = Owner.of(first.pid, store="k1")
        record_app("k1", second.pid)
        record_app("k2", os.getpid())  # another store's application counts for nothing
        first.kill()
        first.wait()
        assert not owner.gone()
        second.kill()
        second.wait()
        assert owner.gone()
        assert open_apps("k1") == [] and not list((tmp_path / "state").rglob(f"k1-{second.pid}*"))
    finally:
        for proc in (first, second):
            if proc.poll() is None:
                proc.kill()
                proc.wait()


def test_a_stale_application_record_is_recognised(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_STATE_HOME", str(tmp_path / "state"))
    path = record_app("k", os.getpid())
    assert open_apps("k") == [os.getpid()]
    path.write_text(json.dumps({"pid": os.getpid(), "ticks": start_ticks(os.getpid()) + 1}))
    assert open_apps("k") == []  # the pid reused by another process: not the application
    assert not path.exists()


def test_the_application_starts_its_pool_as_its_owner_and_says_when_it_leaves(db, monkeypatch,
                                                                               tmp_path):
    monkeypatch.setenv("XDG_STATE_HOME", str(tmp_path / "state"))
    from slopetui.queue import local_pool
    from slopetui.tui.worker_pool import attach_pool

    started: dict[str, object] = {}

    def start(_db, **options):
        started.update(options)
        return 4242, local_pool.default_log()
    monkeypatch.setattr(local_pool, "local_pools", lambda _db: ([], []))
    monkeypatch.setattr(local_pool, "start_detached_pool", start)
    said = attach_pool(db)
    assert started["extra"] == ("--owner-pid", str(os.getpid()))
    assert open_apps(local_pool.store_key(db.url.render_as_string(hide_password=False))) \
        == [os.getpid()]
    assert "leaves once the store has been idle for 60 s" in said


def test_a_pool_the_application_finds_gets_no_owner(db, monkeypatch, tmp_path):
    """A pool already running (`slopetui worker`) keeps its own rules: the application
    starts nothing and tells it nothing (it records itself as open on the store, which
    only a pool started by an application reads)."""
    monkeypatch.setenv("XDG_STATE_HOME", str(tmp_path / "state"))
    from slopetui.queue import local_pool
    from slopetui.tui.worker_pool import attach_pool

    monkeypatch.setattr(local_pool, "local_pools",
                        lambda _db: ([local_pool.LocalPool(4242)], []))
    monkeypatch.setattr(local_pool, "start_detached_pool",
                        lambda *_, **__: pytest.fail("started a second pool"))
    assert "attached to the worker pool of this host (pid 4242" in attach_pool(db)
