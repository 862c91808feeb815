"""A pool's connection budget (slopetui.ops.connection_slots): never more holders than
slots across processes, a slot of a process killed with SIGKILL is free again, and a
budgeted store gives its slot back when idle (the pools on a live PostgreSQL:
tests/integration/test_many_hosts.py)."""

from __future__ import annotations

import multiprocessing as mp
import os
import signal
import time
from pathlib import Path

import pytest

from slopetui.ops.connection_slots import ConnectionSlots, slots_folder
from slopetui.store.database import Database

CTX = mp.get_context("fork")  # spawn would import the test module again: 4 s for six


def _hold_and_count(folder: str, count: int, holders, peak, rounds: int) -> None:
    slots = ConnectionSlots(Path(folder), count)
    for _ in range(rounds):
        slots.acquire()
        with holders.get_lock():
            holders.value += 1
            peak.value = max(peak.value, holders.value)
        time.sleep(0.002)
        with holders.get_lock():
            holders.value -= 1
        slots.release()


def _hold_forever(folder: str) -> None:
    ConnectionSlots(Path(folder), 1).acquire()
    time.sleep(600)


def test_never_more_holders_than_slots(tmp_path):
    holders, peak = CTX.Value("i", 0), CTX.Value("i", 0)
    procs = [CTX.Process(target=_hold_and_count, args=(str(tmp_path), 2, holders, peak, 40))
             for _ in range(6)]
    for p in procs:
        p.start()
    for p in procs:
        p.join(60)
        assert p.exitcode == 0
    assert peak.value == 2  # the six shared two slots, and used both


def test_a_killed_holders_slot_is_free_again(tmp_path):
    holder = CTX.Process(target=_hold_forever, args=(str(tmp_path),))
    holder.start()
    mine = ConnectionSlots(tmp_path, 1)
    deadline = time.monotonic() + 30
    while not (tmp_path / "slot-0").exists() and time.monotonic() < deadline:
        time.sleep(0.01)
    time.sleep(0.2)
    import fcntl
    fd = os.open(tmp_path / "slot-0", os.O_RDWR)
    with pytest.raises(BlockingIOError):  # held by the other process
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    os.close(fd)
    os.kill(holder.pid, signal.SIGKILL)
    holder.join()
    mine.acquire()  # would wait forever if the slot had died with its holder
    assert mine.held
    mine.release()
    assert not mine.held


def test_threads_of_one_process_share_its_slot(tmp_path):
    slots = ConnectionSlots(tmp_path, 1)
    slots.acquire()
    slots.acquire()  # a second connection of the same process: no second slot to wait for
    slots.release()
    assert slots.held
    slots.release()
    assert not slots.held


def test_a_budgeted_store_gives_its_slot_back_when_idle(tmp_path):
    folder = slots_folder("test")
    try:
        slots = ConnectionSlots(folder, 1)
        db = Database(f"sqlite:///{tmp_path / 'x.db'}", slots=slots)
        assert slots.held  # the first read opened a connection, kept for reuse
        db.idle()
        assert not slots.held
        db.stored_revision()
        assert slots.held
        db.dispose()
        assert not slots.held
    finally:
        import shutil
        shutil.rmtree(folder)
    assert folder.parent.stat().st_mode & 0o077 == 0  # the node's /tmp: a private folder
