"""The pruning of old engines' kernel folders (core.jit_cache.prune, use; the pool's
slopetui.queue.warm_up.pool_warm_up): a folder goes only when nothing in it changed for a
day, it is not among the most recently used, and no process holds it. All of it in a
temporary cache ($SLOPETUI_KERNEL_CACHE), never the real one."""

from __future__ import annotations

import logging
import os
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from core import jit_cache
from slopetui.queue import warm_up

DAY = 24 * 3600.0
NOW = time.time()


@pytest.fixture
def base(tmp_path, monkeypatch) -> Path:
    """A kernel cache of the test's own, as cache_base() (not NUMBA_CACHE_DIR)."""
    folder = tmp_path / "numba"
    folder.mkdir()
    monkeypatch.setenv(jit_cache.KERNEL_CACHE_ENV, str(folder))
    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    return folder


def engine(base: Path, name: str, age_s: float) -> Path:
    """An engine's folder as numba leaves it (a checkout's subfolder, an index, a kernel),
    every entry last changed ``age_s`` ago."""
    kernels = base / name / "core_0123"
    kernels.mkdir(parents=True)
    (kernels / "rk4.steps-10.py311.nbi").write_bytes(b"index")
    (kernels / "rk4.steps-10.py311.1.nbc").write_bytes(b"kernel")
    return age(base / name, age_s)


def age(folder: Path, age_s: float) -> Path:
    """Set the times of ``folder`` and of everything in it to ``age_s`` before NOW."""
    when = NOW - age_s
    for root, dirs, files in os.walk(folder):
        for name in (*dirs, *files):
            os.utime(os.path.join(root, name), (when, when))
    os.utime(folder, (when, when))
    return folder


def digest(i: int) -> str:
    return f"{i:016x}"


def test_only_folders_unused_for_a_day_and_not_among_the_most_recent_go(base):
    current = engine(base, jit_cache.source_digest(), 30 * DAY)  # old, but this engine's
    fresh = engine(base, digest(1), 3600.0)  # used an hour ago
    old = {digest(i): engine(base, digest(i), (i + 1) * DAY) for i in range(2, 7)}
    other = engine(base, "notes", 30 * DAY)  # not named like a digest: never ours to remove
    leftover = engine(base, ".pruned-00000000000000ff-1", 0.0)  # a killed prune's
    assert jit_cache.KEEP_RECENT == 2
    # kept: the current engine's, anything used within a day (fresh), and the two most
    # recently used of the others (fresh and the newest old one, 3 days)
    assert sorted(jit_cache.prune(NOW)) == [digest(i) for i in range(3, 7)]
    assert current.is_dir() and fresh.is_dir() and old[digest(2)].is_dir()
    assert not any(old[digest(i)].exists() for i in range(3, 7))
    assert other.is_dir() and not leftover.exists()
    assert sorted(p.name for p in base.iterdir()) == sorted(
        [current.name, fresh.name, digest(2), "notes"])
    assert jit_cache.prune(NOW) == []


def test_a_file_changed_within_the_day_keeps_its_folder(base):
    """An older slopetui locks nothing: a kernel it compiled yesterday is its only sign."""
    for i in range(1, 4):
        engine(base, digest(i), 10 * DAY)
    engine(base, digest(9), 10 * DAY)
    index = base / digest(9) / "core_0123" / "rk4.steps-10.py311.nbi"
    os.utime(index, (NOW - 3600, NOW - 3600))
    assert jit_cache.last_used(base / digest(9)) == pytest.approx(NOW - 3600)
    removed = jit_cache.prune(NOW)
    assert digest(9) not in removed and (base / digest(9)).is_dir()
    assert len(removed) == 3 - jit_cache.KEEP_RECENT + 1  # of the other three, one kept


HOLDER = """import sys
from pathlib import Path
from core.jit_cache import use
fd = use(Path(sys.argv[1]))
print("held" if fd is not None else "not held", flush=True)
sys.stdin.read()
"""


def test_a_folder_a_process_holds_is_not_removed_however_old(base):
    """A process that pointed numba at an old engine's folder days ago (a long-lived pool
    of another version) holds it while it runs: numba would fail to save a kernel it
    compiles into a folder removed under it."""
    for i in range(1, 1 + jit_cache.KEEP_RECENT):
        engine(base, digest(i), DAY)  # the most recent: kept whatever happens
    held = engine(base, digest(9), 10 * DAY)
    holder = subprocess.Popen([sys.executable, "-c", HOLDER, str(held)], text=True,
                              stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                              cwd=Path(jit_cache.CORE_DIR).parent)
    try:
        assert holder.stdout is not None and holder.stdout.readline().strip() == "held"
        assert (held / jit_cache.USED_STAMP).is_file()  # it touched its stamp...
        age(held, 10 * DAY)  # ...days ago
        assert jit_cache.prune(NOW) == [] and held.is_dir()
    finally:
        holder.communicate("", timeout=30)  # it exits: its lock goes with it
    assert jit_cache.prune(NOW) == [digest(9)] and not held.exists()


def test_a_process_that_starts_while_its_folder_is_pruned_makes_a_fresh_one(base):
    """use() waits while a prune holds the folder, then finds it renamed away: it makes a
    new folder rather than keep a lock in the one being deleted."""
    import fcntl

    folder = engine(base, digest(5), 10 * DAY)
    lock = os.open(folder / jit_cache.IN_USE_LOCK, os.O_RDONLY | os.O_CREAT, 0o600)
    fcntl.flock(lock, fcntl.LOCK_EX)  # a prune, at work
    got: list[int | None] = []
    user = threading.Thread(target=lambda: got.append(jit_cache.use(folder)))
    user.start()
    time.sleep(0.2)
    assert user.is_alive()  # waiting for the prune
    trash = base / f".pruned-{digest(5)}-1"
    os.rename(folder, trash)
    os.close(lock)
    user.join(10)
    (fd,) = got
    assert fd is not None
    try:
        now_there = os.stat(folder / jit_cache.IN_USE_LOCK)
        assert (os.fstat(fd).st_dev, os.fstat(fd).st_ino) == (now_there.st_dev, now_there.st_ino)
        assert (folder / jit_cache.USED_STAMP).is_file()
        assert not (folder / "core_0123").exists()  # a fresh folder
    finally:
        os.close(fd)


def test_nothing_is_pruned_when_the_user_chose_numbas_folder(base, monkeypatch, tmp_path):
    engine(base, digest(1), 30 * DAY)
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "theirs"))
    assert jit_cache.prune(NOW) == []
    assert (base / digest(1)).is_dir()


def test_the_lock_and_stamp_users_touch_leave_the_warm_marker_true(base):
    folder = engine(base, jit_cache.source_digest(), 0.0)
    jit_cache.mark_warm()
    assert jit_cache.warmed()
    fd = jit_cache.use(folder)  # every process that loads the kernels does this
    assert fd is not None
    try:
        assert jit_cache.warmed()
    finally:
        os.close(fd)


def test_the_pools_warm_up_prunes_after_it_checked_the_marker(base, caplog):
    engine(base, jit_cache.source_digest(), 0.0)
    jit_cache.mark_warm()
    names = [digest(i) for i in range(1, 2 + jit_cache.KEEP_RECENT)]
    for i, name in enumerate(names):
        engine(base, name, (2 + i) * DAY)
    with caplog.at_level(logging.INFO, logger="slopetui"):
        assert warm_up.pool_warm_up(lambda: False) is not None
    assert not (base / names[-1]).exists()  # the oldest
    assert all((base / name).is_dir() for name in names[:-1])
    assert "removed 1 kernel folders of other engine versions that nobody used for 24 h" \
        in caplog.text
