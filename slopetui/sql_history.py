"""The SQL console's query history: where it is kept, reading it, saving it (no UI).

One JSON string per line (a query may span lines), newest first, without repeats, at most
HISTORY_LIMIT queries. The file is private (HISTORY_MODE): queries can name what a user
studies, and the store beside it is private too. It is rewritten whole in one rename, so
that a crash never leaves half a history.

    history = History(path)
    queries = history.read()        # in a worker thread: file I/O
    history.merge_read(queries)     # on the thread that owns the history (the UI's)
    if history.add(sql):            # True once the file has been read
        history.save()              # in a worker thread
"""

from __future__ import annotations

import json
import os
import threading
from collections.abc import Iterable
from pathlib import Path

from platformdirs import user_data_path

#: Queries kept in the history file.
HISTORY_LIMIT = 200
#: Permissions of the history file: queries can name what a user studies, and the store
#: beside it is private too (0600).
HISTORY_MODE = 0o600


def default_path() -> Path:
    """The user's history file (``~/.local/share/slopetui/sql_history`` on Linux)."""
    return user_data_path("slopetui") / "sql_history"


def merge_history(*sources: Iterable[str], limit: int = HISTORY_LIMIT) -> list[str]:
    """Queries newest first without repeats (the first occurrence wins), at most limit."""
    seen: set[str] = set()
    merged: list[str] = []
    for source in sources:
        for sql in source:
            sql = sql.strip()
            if sql and sql not in seen:
                seen.add(sql)
                merged.append(sql)
    return merged[:limit]


def read_history(path: Path) -> list[str]:
    """One JSON string per line (a query may span lines); unreadable lines are skipped,
    a missing file is an empty history."""
    try:
        lines = path.read_text(encoding="utf-8").splitlines()
    except FileNotFoundError:
        return []
    queries: list[str] = []
    for line in lines:
        try:
            value = json.loads(line)
        except ValueError:
            continue
        if isinstance(value, str):
            queries.append(value)
    return merge_history(queries)


def write_history(path: Path, queries: list[str]) -> None:
    """Replace the file in one rename, so that a crash never leaves half a history; the
    new file is private (HISTORY_MODE), whatever the old one's mode was."""
    path.parent.mkdir(parents=True, exist_ok=True, mode=0o700)
    tmp = path.with_name(f"{path.name}.{os.getpid()}.tmp")
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, HISTORY_MODE)
    os.fchmod(fd, HISTORY_MODE)  # a stale tmp file of a crashed run keeps its old mode
    with os.fdopen(fd, "w", encoding="utf-8") as out:
        out.write("".join(json.dumps(q) + "\n" for q in queries))
    os.replace(tmp, path)


def tighten_history(path: Path) -> None:
    """Make an existing history file private (older versions wrote it 0644)."""
    try:
        mode = path.stat().st_mode & 0o777
    except FileNotFoundError:
        return
    if mode & ~HISTORY_MODE:
        os.chmod(path, HISTORY_MODE)


class History:
    """The queries of one console, newest first, and their file.

    ``read`` and ``save`` do file I/O and may run in worker threads; ``merge_read`` and
    ``add`` change the list and run on one thread (the UI's). Until the file has been
    read, queries are only kept in memory: saving then would drop the file's.
    """

    def __init__(self, path: Path) -> None:
        self.path = path
        self.queries: list[str] = []
        self.loaded = False
        # Saves run in threads; the lock makes the last one to write write the newest.
        self._save_lock = threading.Lock()

    def read(self) -> list[str]:
        """The file's queries (made private first). Raises OSError, UnicodeDecodeError."""
        tighten_history(self.path)
        return read_history(self.path)

    def merge_read(self, queries: list[str]) -> bool:
        """Put the file's queries after those added meanwhile; True when those still have
        to be saved."""
        unsaved = bool(self.queries)
        self.queries = merge_history(self.queries, queries)
        self.loaded = True
        return unsaved

    def add(self, sql: str) -> bool:
        """Record a query as the newest; True when it can be saved now (the file has been
        read; else merge_read says to save it)."""
        self.queries = merge_history([sql], self.queries)
        return self.loaded

    def save(self) -> None:
        """Write the queries to the file. Raises OSError."""
        with self._save_lock:
            write_history(self.path, list(self.queries))
