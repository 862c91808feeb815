"""The queue's default timings and sizes. Light (no SQLAlchemy), so that the command
line can show them in its help without loading a database driver."""

from __future__ import annotations

#: A run whose worker has not sent a heartbeat for this long goes back to the queue (s).
LEASE_S = 60.0
#: Heartbeats come this often (s): a lease survives several lost ones.
HEARTBEAT_S = 10.0
#: Attempts (runs in the kernel) of a run before it is marked failed.
MAX_ATTEMPTS = 3
#: Runs a worker claims at once (runs with the same solver settings and tau; see
#: worker_process): the lanes of one call of the batched kernels, whose lanes share tau
#: (core.batch: 64 lanes are 8 AVX-512 vectors of doubles). A plane of n x m points has n
#: runs per tau. Memory bounds it, not this: MEMORY_MIB cuts a batch of long windows.
DEFAULT_BATCH = 64
#: A worker's memory for the runs of one batch (MiB): the batch is cut to the runs whose
#: windows, traces, delay rings and lambda_max logs (core.solve.memory_of) fit in it, as
#: batch_memory.charge counts them. The paper's run (Euler, dt 1e-3, t_end 1e5, window
#: 1000, tau 10) lays out 9.5 MiB, so a batch of 64 is charged 649 MiB and kept whole (96
#: such runs fit; at tau 100, 10.8 MiB a run, 88); at window 1e4 a run lays out 92 MiB and
#: a batch is cut to 8 (benchmarks/bench_memory.py: the added RSS stays within 0.96 of the
#: charge). 1 GiB and the process's ~0.2 GiB let a 2-core machine with 24 GiB run its two
#: workers with room left.
MEMORY_MIB = 1024
#: The niceness a worker process takes (nice(2), relative to the pool's): workers keep both
#: cores busy for hours, and the researcher's terminal (the app, `slopetui show`, an
#: editor) should not wait behind them. At the same priority the app took a median 100
#: ms and a p95 of 180 ms to switch screens with two workers busy (benchmarks/bench_tui.py),
#: most of it waiting for a core. A nice worker loses nothing on an otherwise idle machine.
WORKER_NICE = 10
#: A pool that leaves on its own (--exit-when-idle; the application's pool, once the
#: application has quit) waits this long with nothing claimable before it leaves while
#: something may still come back: a paused sweep's queued runs, or the application's user
#: starting it again (s). A drained queue under --exit-when-idle is left at once.
IDLE_GRACE_S = 60.0
