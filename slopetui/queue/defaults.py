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
#: A worker's memory for the runs of one batch (MiB): the batch is cut to the runs whose
#: windows, traces, delay rings and lambda_max logs (core.solve.memory_of) fit in it. The
#: paper's run needs ~10 MB, so a batch of 32 takes ~0.3 GiB; at window 1e5 a run needs
#: ~1 GB (issue 17 measured 185 MiB + ~48 MB a run at window 1e4, ~15 GiB for 32 runs at
#: 1e5), and 1 GiB lets a 2-core machine with 24 GiB run its two workers with room left.
MEMORY_MIB = 1024
