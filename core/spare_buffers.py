"""Arrays a batched kernel call writes its samples into, kept for the next call.

A call of the batched kernels (core.batch) fills each lane's analysis window and trace,
one row of 5 values a sample: at the paper's share of the run and RK4's step of 1e-2, 1.6
MB a lane, 100 MB for a call of 64 lanes. A new array of that size is new memory: each of
its pages is faulted in, and zeroed by the kernel, as the samples first reach it. On this
machine (a virtual machine, 4 KiB pages) that cost about 2 us a page, up to 0.2 s for
100 MB when the kernel compacts memory for huge pages: 19% of a batched RK4 call
(benchmarks/bench_kernels.py: 6.0 against 4.9 ns per point-step with the arrays reused,
load 8-13). A worker computes batch after batch with the same settings, whose calls
need arrays of the same shapes, and the trajectories of the last batch are written and
dropped before the next: their arrays can be written again, without a fault.

An array is handed out again only once nothing but this module refers to it: the
trajectories of a call are views of its arrays, and as long as any of them (or anything
made from them without a copy) is alive, the array is not reused. A miss (no free array
of the shape) first lets go of the free arrays of other shapes, so that the module never
holds more than the last calls used (a worker's memory budget counts them:
slopetui.queue.batch_memory).
"""

from __future__ import annotations

import sys
import threading

import numpy as np

#: At most this many arrays are kept: the sample arrays of a batch's calls (two each,
#: window and trace; a worker's batch of one tau is one call, core.batch.simulate_batch
#: makes one call a tau and LANES points).
KEPT = 8
#: sys.getrefcount of a kept array that nothing else refers to, in _free: the list that
#: keeps it and getrefcount's argument.
UNREFERENCED = 2

_kept: list[np.ndarray] = []
#: Two threads (a worker's, the application's) must not both take one free array.
_lock = threading.Lock()


def sample_array(shape: tuple[int, ...]) -> np.ndarray:
    """A float64 array of ``shape`` to be written whole before it is read (its contents are
    undefined, as np.empty's): a kept one that nothing refers to any more, or a new one,
    kept for later calls."""
    with _lock:
        free = [i for i in range(len(_kept)) if _free(i)]
        for i in free:
            if _kept[i].shape == shape:
                return _kept[i]  # referenced by the caller's frame before the lock is let go
        # a miss: the free arrays of other shapes are from other settings; let them go
        _kept[:] = [a for i, a in enumerate(_kept) if i not in free]
        array = np.empty(shape)
        if len(_kept) < KEPT:
            _kept.append(array)
        return array


def _free(i: int) -> bool:
    """Whether nothing but _kept refers to its array i."""
    return sys.getrefcount(_kept[i]) == UNREFERENCED


def release() -> None:
    """Let go of every kept array (memory the next call faults in again)."""
    with _lock:
        _kept.clear()
