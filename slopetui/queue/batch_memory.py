"""How many runs of a claimed batch fit a worker's memory budget.

The batched kernels (Euler and RK4: worker_process.BATCHED_METHODS) hold every lane's
buffers at once, from the call's start to its end: each run's window and trace samples
and lambda_max logs, and the delay ring of every lane, N x lanes x 8 bytes per buffered
variable (m_x for Euler, m_x and m_y for RK4) and as much again for the tangent with
lambda_max. core.solve.memory_of counts each run's share of all of it (its ring at
RING_BYTES a delay step, the tangent's always included), so a batch needs the sum over
its runs. A batch claimed whole shares its solver settings and tau (claims.claim_batch),
so its runs need the same; the sum holds for any mix all the same (the ring grows with
tau / dt, the samples and logs with the settings). The worker keeps the longest prefix
of the batch whose needs add up to at most the budget, and always at least one run (a
run alone over the budget is core.solve's to refuse, at 2 GiB), and gives the rest back
to the queue unstarted (no attempt charged), for itself or another worker. A batch
computed run by run holds one run's buffers at a time and is not cut.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from core.params import ParameterError

if TYPE_CHECKING:
    from slopetui.queue.jobs import Job

MIB = 1024**2
#: What a batch adds to a worker's memory, over what memory_of counts for its runs: the
#: batched kernel's result arrays and numpy's temporaries. Measured with
#: benchmarks/bench_memory.py (peak RSS of one batched Euler call less the process's
#: baseline of ~156 MiB): 1.04 for 32 runs at window 1e4, 1.17 for 8, 1.30 for 8 at
#: window 1e5; the largest is taken, so that a batch cut to the budget stays within it.
#: (Measured with the kernels of 16 slots in blocks, before lanes shared tau; the rings
#: of the shared-tau kernels are what memory_of counts, at most.)
OVERHEAD = 1.3


def run_bytes(job: Job) -> int:
    """The bytes the run lays out (core.solve.memory_of); 0 for inputs the engine refuses
    (the run fails on its own when computed, saying why)."""
    from core.solve import make_grid, memory_of
    try:
        return memory_of(make_grid(job.params, job.settings), job.settings).total
    except ParameterError:
        return 0


def fitting(batch: Sequence[Job], budget_bytes: int) -> int:
    """How many leading runs of ``batch`` fit ``budget_bytes`` together, each counted at
    OVERHEAD times what it lays out (at least 1 of a non-empty batch)."""
    used, n = 0.0, 0
    for job in batch:
        used += OVERHEAD * run_bytes(job)
        if n and used > budget_bytes:
            break
        n += 1
    return n
