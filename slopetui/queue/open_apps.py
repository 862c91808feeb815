"""The applications open on a store on this host: each one records itself when it starts
or finds the store's pool, so that the pool an application started stays while any
application of its store is open, not only the one that started it
(slopetui.queue.idle_exit.Owner).

A record is ``<user state dir>/apps/<store key>-<pid>.json`` (0600 in a 0700 folder, in
a folder of its own: the pool files' glob must not take it for a pool) holding the pid and
its start time. Nothing removes it when the application quits: a record whose process is
gone, or whose pid now names a process started at another time, is stale and removed by
the next reader.
"""

from __future__ import annotations

import contextlib
import json
import os
from pathlib import Path

from slopetui.queue.local_pool import is_alive, pools_dir, start_ticks


def apps_dir() -> Path:
    return pools_dir().parent / "apps"


def record_app(key: str, pid: int) -> Path:
    """Record the application ``pid`` as open on the store whose key
    (local_pool.store_key) is ``key``."""
    path = apps_dir() / f"{key}-{pid}.json"
    path.parent.mkdir(parents=True, exist_ok=True, mode=0o700)
    tmp = path.with_suffix(f".tmp{os.getpid()}")
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
    with os.fdopen(fd, "w", encoding="utf-8") as out:
        json.dump({"pid": pid, "ticks": start_ticks(pid)}, out)
    os.replace(tmp, path)  # a reader never sees half a file
    return path


def open_apps(key: str) -> list[int]:
    """The pids of the applications open on the store whose key is ``key``; stale
    records are removed."""
    found = []
    for path in apps_dir().glob(f"{key}-*.json"):
        try:
            record = json.loads(path.read_text())
            pid, ticks = int(record["pid"]), record.get("ticks")
        except (OSError, ValueError, KeyError, TypeError):
            continue  # being written, or not ours
        if is_alive(pid) and (ticks is None or start_ticks(pid) in (None, ticks)):
            found.append(pid)
        else:
            with contextlib.suppress(FileNotFoundError):
                path.unlink()
    return sorted(found)
