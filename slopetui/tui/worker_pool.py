"""The worker pool the application computes with: this host's pool on the store, found or
started, and what to tell the user about it.

The pool lives on after the application quits: queued work is never lost by quitting. A
pool the application starts has it as its owner (``--owner-pid``): it leaves once the
application has quit and the store has been idle for the grace period
(slopetui.queue.idle_exit). A pool found running (``slopetui worker``) keeps its own
rules.
"""

from __future__ import annotations

import os

from slopetui.queue import local_pool
from slopetui.queue.defaults import IDLE_GRACE_S
from slopetui.queue.open_apps import record_app
from slopetui.store.database import Database


def attach_pool(db: Database) -> str:
    """Find this host's pool on ``db`` or start one, and say which (it may take a few
    seconds: a background action's)."""
    # open on this store: a pool another application started stays while it is
    record_app(local_pool.store_key(db.url.render_as_string(hide_password=False)), os.getpid())
    pools, _ = local_pool.local_pools(db)  # a pool still warming up has no workers yet
    if pools:
        n = sum(len(p.workers) for p in pools)
        return (f"attached to the worker pool of this host (pid "
                f"{', '.join(str(p.pid) for p in pools)}, {n} workers)")
    pid, log = local_pool.start_detached_pool(db, extra=("--owner-pid", str(os.getpid())))
    return (f"worker pool started (pid {pid}, log {log}); after you quit it finishes the "
            f"queue, then leaves once the store has been idle for {IDLE_GRACE_S:g} s")
