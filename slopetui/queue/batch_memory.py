"""How many runs of a claimed batch fit a worker's memory budget.

The batched kernels (Euler and RK4: run_batches.BATCHED_METHODS) hold every lane's
buffers at once, from the call's start to its end: each run's window and trace samples
and lambda_max logs, and the delay ring of every lane, N x lanes x 8 bytes per buffered
variable (m_x for Euler, m_x and m_y for RK4) and as much again for the tangent with
lambda_max. core.solve.memory_of counts each run's share of all of it (its ring at
RING_BYTES a delay step, the tangent's always included), so a batch needs the sum over
its runs. A batch claimed whole shares its solver settings and tau (claims.claim_batch),
so its runs need the same; the sum holds for any mix all the same (the ring grows with
tau / dt, the samples and logs with the settings). Beyond the sum, a kernel call pads its
lanes to whole vectors with copies of its last run (core.batch.VECTOR), each holding a
run's buffers, and the analysis after the call (core.point.run_batch) takes up to one
run's more at a time: a lane re-integrated by the stiff scheme, in arrays of its own
until they are copied into the lane's, or a window's classification. charge counts all
of it. The worker keeps the longest prefix of the batch whose charge is at most the
budget, and always at least one run (a run alone over the budget is core.solve's to
refuse, at 2 GiB), and gives the rest back to the queue unstarted (no attempt charged),
for itself or another worker. A batch computed run by run holds one run's buffers at a
time and is not cut.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

from core.params import ParameterError

if TYPE_CHECKING:
    from slopetui.queue.jobs import Job

MIB = 1024**2
#: What each run of a batch (padding lanes included) adds to a worker's memory, over what
#: memory_of counts for it, and (REDO) how many of its largest run's bytes the analysis
#: adds once. Measured with benchmarks/bench_memory.py (peak RSS of core.run_batch, Euler
#: with lambda_max, t_end 2 x window, less the process's baseline of ~159 MiB; table in
#: docs/speed.md): the batch's arrays are what memory_of counts, so the added RSS over it
#: tends to 1 with more lanes (1.03 for 32 runs at window 1e4, 1.04 at 1e5), and the rest
#: is about one run: 1.15 of it (1 run at window 1e4 or 1e5, re-integrated by the stiff
#: scheme: --k 4 --params a=0.3 delta=0.1), 0.98 (8 runs at 1e4, none re-integrated).
#: Rounded up, so that a batch cut to the budget stays within it: every batch measured
#: took at most 0.96 of its charge (8 runs at window 1e4, all 8 re-integrated). (Before
#: run_batch wrote re-integrations over the lane's own samples, each re-integrated lane
#: kept its samples twice: 1.60 for 32 runs at window 1e5, of which 18 re-integrated.)
OVERHEAD = 1.05
REDO = 1.25


def run_bytes(job: Job) -> int:
    """The bytes the run lays out (core.solve.memory_of); 0 for inputs the engine refuses
    (the run fails on its own when computed, saying why)."""
    from core.solve import make_grid, memory_of
    try:
        return memory_of(make_grid(job.params, job.settings), job.settings).total
    except ParameterError:
        return 0


def charge(sizes: Sequence[int]) -> float:
    """The bytes a batch of runs that lay out ``sizes`` (run_bytes, in order) is counted
    at: OVERHEAD times their sum with the lanes the kernel call pads them with (copies of
    the last run, core.batch), and REDO times the largest (0 for no runs)."""
    from core.batch import MIN_LANES, VECTOR  # numba's: imported where batches are computed
    if not sizes:
        return 0.0
    pad = -len(sizes) % VECTOR if len(sizes) >= MIN_LANES else 0
    return OVERHEAD * (sum(sizes) + pad * sizes[-1]) + REDO * max(sizes)


def fitting_sizes(sizes: Sequence[int], budget_bytes: int) -> int:
    """How many leading runs of the sizes ``sizes`` fit ``budget_bytes`` together, counted
    by charge (at least 1 of a non-empty batch)."""
    n = 0
    while n < len(sizes) and (n == 0 or charge(sizes[:n + 1]) <= budget_bytes):
        n += 1
    return n


def fitting(batch: Sequence[Job], budget_bytes: int) -> int:
    """How many leading runs of ``batch`` fit ``budget_bytes`` together, counted by charge
    (at least 1 of a non-empty batch)."""
    return fitting_sizes([run_bytes(job) for job in batch], budget_bytes)
