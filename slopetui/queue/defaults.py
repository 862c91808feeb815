"""The queue's default timings and sizes. Light (no SQLAlchemy), so that the command
line can show them in its help without loading a database driver."""

from __future__ import annotations

#: A run whose worker has not sent a heartbeat for this long goes back to the queue (s).
LEASE_S = 60.0
#: Heartbeats come this often (s): a lease survives several lost ones.
HEARTBEAT_S = 10.0
#: Attempts (runs in the kernel) of a run before it is marked failed.
MAX_ATTEMPTS = 3
#: Runs a worker claims at once (runs with the same solver settings; see worker_process).
DEFAULT_BATCH = 32
