"""Where numba caches compiled kernels, keyed by the source of the whole engine.

numba's ``cache=True`` invalidates a kernel's cache entry only when the kernel's *own*
file changes. The kernels in core.euler and core.rk4 inline the equations of core.model
and the helpers of core.recording, so an edit there would silently keep running the old
machine code (we saw a deliberately broken tangent pass the tests that way). We therefore
point numba at a cache folder named after a hash of every core/*.py file: any edit to
the engine gets a fresh folder and a fresh compile.

The folder is node-local: $SLOPETUI_KERNEL_CACHE if set, else $XDG_CACHE_HOME (default
~/.cache) unless that is on a network file system (a cluster's shared home: every node
writing into one numba cache at start corrupts it, numba#4807, #10128), in which case the
temporary folder ($TMPDIR, default /tmp), which is each node's own.

A user-set NUMBA_CACHE_DIR is respected as is.

The warm-up's marker (``warmed.json`` in that folder, ``mark_warm`` and ``warmed``) says
that a warm-up left every kernel it runs compiled there, and what numba decides a load
on: while it still matches, a pool may skip its own serial warm-up and let its workers
load the kernels at once (slopetui.queue.warm_up).

Old folders. Every edit of the engine leaves a folder behind (~3 MB each; a day of work on
core/ left 130, 420 MB), and another installed version of slopetui (another venv, another
checkout) may be using any of them right now: numba writes a kernel it compiles into the
folder it was pointed at when the kernel was decorated, and fails if that folder was
removed since. ``prune`` (a pool calls it after its warm-up) therefore removes only the
folders nobody is known to use:

* every process that points numba at a folder (``configure``) holds a shared lock on the
  folder's ``in-use.lock`` until it exits, and touches its ``used`` stamp. ``prune``
  takes the lock exclusively, without waiting, before it renames the folder away (then
  deletes it): a folder such a process uses is never removed, and a process that starts
  meanwhile finds the folder whole or gone, never half deleted (it then makes a fresh one);
* versions of slopetui older than this lock nothing: what they show is their files'
  times (a compilation, a warm-up's marker). A folder is removed only when nothing in it
  changed for PRUNE_IDLE_S (a day), and the KEEP_RECENT most recently used folders stay
  whatever their age (switching back to yesterday's branch or version loads its kernels
  instead of compiling them again, ~20 s). An old version's process that has run for
  more than a day without compiling can still lose its folder: it compiles the kernel it
  misses again, once, and a run that was compiling it fails one attempt.
"""

from __future__ import annotations

import fcntl
import hashlib
import json
import os
import re
import shutil
import stat
import sys
import tempfile
import time
from functools import lru_cache
from importlib import metadata
from pathlib import Path
from typing import Any

from core.mounts import network_filesystem

CORE_DIR = Path(__file__).resolve().parent
#: A folder for the kernel cache chosen by the user or a job script (e.g. the Slurm
#: script of `slopetui cluster slurm` names the node's scratch space).
KERNEL_CACHE_ENV = "SLOPETUI_KERNEL_CACHE"
#: The warm-up's marker, in kernel_folder() (see the module docstring).
WARM_MARKER = "warmed.json"
#: In each engine's folder: the lock its users hold shared and ``prune`` exclusively, and
#: the stamp its users touch (see the module docstring, "Old folders").
IN_USE_LOCK = "in-use.lock"
USED_STAMP = "used"
#: ``prune`` removes a folder in which nothing changed for this long (s)...
PRUNE_IDLE_S = 24 * 3600.0
#: ...unless it is one of this many most recently used (besides the current engine's).
KEEP_RECENT = 2
#: The name of an engine's folder (source_digest()) and of one being deleted by ``prune``.
_DIGEST = re.compile(r"[0-9a-f]{16}")
_PRUNED = ".pruned-"
#: This process's shared lock on its engine's folder (``configure``), held until it exits.
_in_use: int | None = None


def source_digest() -> str:
    """A short hash of the engine's Python sources."""
    h = hashlib.sha256()
    for path in sorted(CORE_DIR.glob("*.py")):
        h.update(path.name.encode())
        h.update(path.read_bytes())
    return h.hexdigest()[:16]


@lru_cache(maxsize=1)  # a fresh private folder (the fallback) is made once a process
def _node_local() -> Path:
    """A folder of this user's in the node's temporary folder. /tmp is shared by every
    user of the node, and numba's cache holds pickles that it loads: a folder that another
    user made or may write into would let them run code as us, so such a folder is not
    used (a fresh private one is, and kernels are compiled again)."""
    folder = Path(tempfile.gettempdir()) / f"slopetui-kernels-{os.getuid()}"
    try:
        folder.mkdir(mode=0o700, exist_ok=True)
        info = folder.lstat()
        if (stat.S_ISDIR(info.st_mode) and info.st_uid == os.getuid()
                and not info.st_mode & 0o022):
            return folder
    except OSError:
        pass
    return Path(tempfile.mkdtemp(prefix="slopetui-kernels-"))


def cache_base() -> Path:
    """The folder that holds every engine's kernels (see the module docstring)."""
    chosen = os.environ.get(KERNEL_CACHE_ENV)
    if chosen:
        return Path(chosen)
    home = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "slopetui" / "numba"
    return _node_local() if network_filesystem(home) else home


def cache_dir() -> Path:
    """cache_base()/<digest of the engine's sources>."""
    return cache_base() / source_digest()


def configure() -> None:
    """Point numba's cache at cache_dir(), and hold it as in use (``use``); must run before
    any kernel is decorated."""
    global _in_use
    if os.environ.get("NUMBA_CACHE_DIR"):
        return
    import numba  # here, not at the top: source_digest() alone must not load numba

    folder = cache_dir()
    numba.config.CACHE_DIR = str(folder)
    if _in_use is None:
        _in_use = use(folder)


def use(folder: Path) -> int | None:
    """Hold ``folder`` as in use by this process (a shared lock on its IN_USE_LOCK, made
    with the folder if need be) and touch its USED_STAMP. Returns the lock's descriptor,
    to be kept open while the folder is used (closing it releases the lock), or None if
    the folder cannot be written (numba will not cache there either)."""
    lock = folder / IN_USE_LOCK
    for _ in range(10):  # each turn: the folder was pruned while we waited for the lock
        try:
            folder.mkdir(parents=True, exist_ok=True)
            fd = os.open(lock, os.O_RDONLY | os.O_CREAT | os.O_CLOEXEC, 0o600)
        except FileNotFoundError:
            continue
        except OSError:
            return None
        try:
            fcntl.flock(fd, fcntl.LOCK_SH)  # waits while a prune holds it (an instant)
            if _still_there(fd, lock):
                (folder / USED_STAMP).touch()
                return fd
        except FileNotFoundError:
            pass  # renamed away by a prune: make a fresh folder
        except OSError:
            os.close(fd)
            return None
        os.close(fd)
    return None


def _still_there(fd: int, lock: Path) -> bool:
    """Whether the open lock file ``fd`` is still the one at ``lock``: a prune that renamed
    its folder away leaves the descriptor on the old file (FileNotFoundError if nothing is
    at ``lock`` now)."""
    held, there = os.fstat(fd), os.stat(lock)
    return (held.st_dev, held.st_ino) == (there.st_dev, there.st_ino)


def last_used(folder: Path) -> float:
    """When ``folder`` was last used, as far as its files tell (epoch seconds): the newest
    modification of anything in it (a kernel compiled, a marker written, USED_STAMP
    touched), except the lock, which ``prune`` may create; the folder's own time if it
    holds nothing else."""
    newest = None
    for root, dirs, files in os.walk(folder):
        for name in (*dirs, *files):
            if name == IN_USE_LOCK and root == str(folder):
                continue
            try:
                mtime = os.lstat(os.path.join(root, name)).st_mtime
            except OSError:
                continue
            newest = mtime if newest is None else max(newest, mtime)
    return folder.lstat().st_mtime if newest is None else newest


def prune(now: float | None = None) -> list[str]:
    """Remove the folders of other engines in cache_base() that nobody uses (see the
    module docstring, "Old folders"); returns their names. Nothing when the user chose
    numba's folder (NUMBA_CACHE_DIR): the folders here are then not in use by us at all,
    and their owner may be another tool. Only folders named like a source digest are
    looked at, since $SLOPETUI_KERNEL_CACHE may name a folder that holds other things."""
    if os.environ.get("NUMBA_CACHE_DIR"):
        return []
    base, current = cache_base(), source_digest()
    now = time.time() if now is None else now
    try:
        entries = [entry for entry in os.scandir(base) if entry.is_dir(follow_symlinks=False)]
    except OSError:
        return []
    for entry in entries:  # left by a prune that was killed (or is deleting it now)
        if entry.name.startswith(_PRUNED):
            shutil.rmtree(entry.path, ignore_errors=True)
    used = {}
    for entry in entries:
        if _DIGEST.fullmatch(entry.name) and entry.name != current:
            try:
                used[Path(entry.path)] = last_used(Path(entry.path))
            except OSError:  # removed meanwhile
                continue
    recent = sorted(used, key=used.__getitem__, reverse=True)[:KEEP_RECENT]
    removed = []
    for folder, at in used.items():
        if folder not in recent and now - at >= PRUNE_IDLE_S and _remove(folder, now):
            removed.append(folder.name)
    return removed


def _remove(folder: Path, now: float) -> bool:
    """Remove ``folder`` if no process holds it (``use``) and nothing in it changed since
    the caller looked: under its lock, taken exclusively without waiting, rename it away,
    then delete it."""
    lock = folder / IN_USE_LOCK
    try:
        fd = os.open(lock, os.O_RDONLY | os.O_CREAT | os.O_CLOEXEC, 0o600)
    except OSError:  # gone already, or not ours to write
        return False
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)  # BlockingIOError: in use
        if not _still_there(fd, lock):
            return False  # another prune renamed it away, and a process made it again
        if now - last_used(folder) < PRUNE_IDLE_S:
            return False  # used since the caller looked
        trash = folder.with_name(f"{_PRUNED}{folder.name}-{os.getpid()}")
        os.rename(folder, trash)
    except OSError:
        return False
    finally:
        os.close(fd)  # a process waiting for the lock now finds the folder gone
    shutil.rmtree(trash, ignore_errors=True)
    return True


def kernel_folder() -> Path:
    """The folder numba caches the kernels in: NUMBA_CACHE_DIR if the user set it, else
    cache_dir() (configure())."""
    return Path(os.environ.get("NUMBA_CACHE_DIR") or cache_dir())


def compiled(module: str) -> bool:
    """Whether numba's cache holds a compiled kernel of ``core.<module>`` (an index file
    ``<module>.<function>-<line>.py<version>.nbi``): if not, the next call compiles it."""
    return any(kernel_folder().rglob(f"{module}.*.nbi"))


def _cache_state(folder: Path) -> dict[str, Any]:
    """What a load from ``folder`` depends on. numba loads a kernel when the index file of
    its function holds an entry under the same key, else compiles it and rewrites the
    index: the index's numba version, the function's source (numba 0.68 hashes the file;
    older versions used its mtime and size: both are here), its bytecode (the Python
    version) and the machine (target triple, CPU name and features, which
    NUMBA_CPU_NAME and NUMBA_CPU_FEATURES override). The folder's every file with its
    size and mtime: any compilation since (a new signature, another checkout of the
    engine, whose kernels numba files in a folder named after the checkout's path)
    changes it; not the lock and stamp that every process using the folder touches
    (``use``)."""
    import llvmlite.binding as llvm  # ~0.1 s; what numba's codegen asks for its key

    files = {}
    for path in sorted(folder.rglob("*")):
        if (path.is_file() and path.name not in (WARM_MARKER, IN_USE_LOCK, USED_STAMP)
                and not path.name.endswith(".tmp")):
            info = path.stat()
            files[str(path.relative_to(folder))] = [info.st_size, info.st_mtime_ns]
    sources = {}
    for path in sorted(CORE_DIR.glob("*.py")):
        info = path.stat()
        sources[path.name] = [info.st_size, info.st_mtime_ns]
    return {
        "core": str(CORE_DIR), "sources": sources,
        "python": sys.version, "platform": sys.platform,
        "numba": metadata.version("numba"), "llvmlite": metadata.version("llvmlite"),
        "triple": llvm.get_process_triple(), "cpu": llvm.get_host_cpu_name(),
        "features": llvm.get_host_cpu_features().flatten(),
        "cpu_env": [os.environ.get("NUMBA_CPU_NAME"), os.environ.get("NUMBA_CPU_FEATURES")],
        "files": files,
    }


def mark_warm() -> None:
    """Record, after a warm-up that ran every kernel it covers (serially: nobody compiled
    beside it), that kernel_folder() holds them all and what their loading depends on.
    Written whole or not at all (a temporary file renamed over the marker)."""
    folder = kernel_folder()
    state = _cache_state(folder)
    if not state["files"]:  # nothing cached (numba caching off?): nothing to vouch for
        return
    temporary = folder / f"{WARM_MARKER}.{os.getpid()}.tmp"
    temporary.write_text(json.dumps(state, sort_keys=True))
    temporary.replace(folder / WARM_MARKER)


def warmed() -> bool:
    """Whether the marker of a warm-up is there and still describes kernel_folder() and
    this interpreter, numba and machine (mark_warm): a warm-up would then only load."""
    folder = kernel_folder()
    try:
        recorded = json.loads((folder / WARM_MARKER).read_text())
    except (OSError, ValueError):
        return False
    return bool(recorded == _cache_state(folder))
