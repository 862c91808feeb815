"""The statuses of sweeps and runs: the values the store's CHECK constraints allow
(slopetui.store.models). Light, so that a command line can offer them as choices
without loading SQLAlchemy."""

from __future__ import annotations

#: active: its runs are handed to workers; paused: kept queued but not handed out;
#: cancelled: its queued runs were cancelled (runs already running finish).
SWEEP_STATUSES = ("active", "paused", "cancelled")
#: The life of a run: queued -> running -> done | failed, or queued -> cancelled. A running
#: run whose worker dies goes back to queued when its lease expires.
RUN_STATUSES = ("queued", "running", "done", "failed", "cancelled")
