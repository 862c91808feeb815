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
"""

from __future__ import annotations

import hashlib
import os
import stat
import tempfile
from functools import lru_cache
from pathlib import Path

from core.mounts import network_filesystem

CORE_DIR = Path(__file__).resolve().parent
#: A folder for the kernel cache chosen by the user or a job script (e.g. the Slurm
#: script of `slopetui cluster slurm` names the node's scratch space).
KERNEL_CACHE_ENV = "SLOPETUI_KERNEL_CACHE"


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


def compiled(module: str) -> bool:
    """Whether numba's cache holds a compiled kernel of ``core.<module>`` (an index file
    ``<module>.<function>-<line>.py<version>.nbi``): if not, the next call compiles it."""
    folder = Path(os.environ.get("NUMBA_CACHE_DIR") or cache_dir())
    return any(folder.rglob(f"{module}.*.nbi"))
