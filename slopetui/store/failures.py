"""Why a database file cannot be opened or written, in one line a researcher can act on.

SQLite says "unable to open database file" for a missing folder, a read-only folder, a
read-only file system and a path under /proc alike, and "disk I/O error" for a full disk
on some file systems: its own words do not tell the cause. These functions look at the
file system to name it, and always name the file.
"""

from __future__ import annotations

import errno
import os
from pathlib import Path


class StoreError(Exception):
    """The database cannot be opened or used; the message says why and what to do."""


class DatabaseFailure(StoreError):
    """The database failed while in use (a full disk, a damaged file, a server gone, a
    lock held too long), raised by ``Database``'s sessions, transactions and connections
    in place of SQLAlchemy's error, which stays its ``__cause__``: the one place the
    store's driver errors become the store's own, so that no layer above it needs to know
    SQLAlchemy. The message names the store and the cause (``describe``)."""


#: Words of SQLite's messages for a file that is not (or no longer) a valid database.
DAMAGE_WORDS = ("malformed", "file is not a database", "database disk image")
#: Words of SQLite's messages for a write that found no room.
FULL_WORDS = ("database or disk is full", "no space left")
#: Less room than this beside a SQLite file is a full disk: a result is a few kB, a
#: checkpoint of the write-ahead log copies up to 4 MB (SQLite's default 1000 pages).
MIN_FREE_BYTES = 1 << 20


def path_problem(path: Path) -> str | None:
    """What stops a database (and its -wal and -shm files) from living at ``path``, if the
    file system shows it; None if nothing visible does."""
    if path.parts[1:2] in (("proc",), ("sys",), ("dev",)):
        return f"/{path.parts[1]} is a virtual file system of the kernel, not a place for a file"
    folder = path.parent
    if not folder.exists():
        return (f"the folder {folder} does not exist (create it first, or leave out --db "
                "to use the default store)")
    if not folder.is_dir():
        return f"{folder} is not a folder"
    if path.exists() and not path.is_file():
        return f"{path} is not a regular file"
    if os.statvfs(folder).f_flag & os.ST_RDONLY:
        return f"{folder} is on a read-only file system"
    if not os.access(folder, os.W_OK | os.X_OK):
        return (f"no permission to write in {folder} (SQLite creates {path.name}-wal and "
                f"{path.name}-shm beside the file)")
    if path.exists() and not os.access(path, os.R_OK | os.W_OK):
        return f"no permission to read and write {path}"
    return None


def free_bytes(path: Path) -> int | None:
    """The bytes free to this user on the file system of ``path``'s folder (None: unknown)."""
    try:
        st = os.statvfs(path.parent)
    except OSError:
        return None
    return st.f_bavail * st.f_frsize


def describe(path: Path | None, reason: str) -> str:
    """One line for a failure of the database at ``path`` (None: not a SQLite file), from
    the database's own ``reason``."""
    if path is None:
        return reason
    lowered = reason.lower()
    if any(word in lowered for word in DAMAGE_WORDS):
        return (f"the database file {path} is damaged ({reason}): `slopetui db check` "
                f"tells what is broken; restore a backup ({path.name}.bak-* beside it) or "
                "copy out what is readable with the sqlite3 shell's .recover")
    free = free_bytes(path)
    if any(word in lowered for word in FULL_WORDS) or (
            "disk i/o error" in lowered and free is not None and free < MIN_FREE_BYTES):
        return f"cannot write {path}: the disk is full ({reason})"
    problem = path_problem(path)
    if problem is not None:
        return f"cannot use the database {path}: {problem} ({reason})"
    return f"database {path}: {reason}"


def os_failure(path: Path, exc: OSError) -> StoreError:
    """A StoreError for an OSError met while creating the database file or its folder."""
    if exc.errno == errno.ENOSPC:
        return StoreError(f"cannot create {path}: the disk is full")
    problem = path_problem(path)
    cause = problem or exc.strerror or str(exc)
    return StoreError(f"cannot create the database {path}: {cause}")
