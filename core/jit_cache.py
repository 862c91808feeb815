"""Where numba caches compiled kernels, keyed by the source of the whole engine.

numba's ``cache=True`` invalidates a kernel's cache entry only when the kernel's *own*
file changes. The kernels in core.euler and core.rk4 inline the equations of core.model
and the helpers of core.recording, so an edit there would silently keep running the old
machine code (we saw a deliberately broken tangent pass the tests that way). We therefore
point numba at a cache folder named after a hash of every core/*.py file: any edit to
the engine gets a fresh folder and a fresh compile.

A user-set NUMBA_CACHE_DIR is respected as is.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

CORE_DIR = Path(__file__).resolve().parent


def source_digest() -> str:
    """A short hash of the engine's Python sources."""
    h = hashlib.sha256()
    for path in sorted(CORE_DIR.glob("*.py")):
        h.update(path.name.encode())
        h.update(path.read_bytes())
    return h.hexdigest()[:16]


def cache_dir() -> Path:
    """$XDG_CACHE_HOME/slopetui/numba/<digest> (default ~/.cache/...)."""
    base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    return base / "slopetui" / "numba" / source_digest()


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
