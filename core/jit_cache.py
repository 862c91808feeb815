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
"""

from __future__ import annotations

import hashlib
import json
import os
import stat
import sys
import tempfile
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
    """Point numba's cache at cache_dir(); must run before any kernel is decorated."""
    if os.environ.get("NUMBA_CACHE_DIR"):
        return
    import numba  # here, not at the top: source_digest() alone must not load numba

    numba.config.CACHE_DIR = str(cache_dir())


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
    changes it."""
    import llvmlite.binding as llvm  # ~0.1 s; what numba's codegen asks for its key

    files = {}
    for path in sorted(folder.rglob("*")):
        if path.is_file() and path.name != WARM_MARKER and not path.name.endswith(".tmp"):
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
