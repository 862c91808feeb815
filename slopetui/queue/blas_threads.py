"""One BLAS thread in each worker process, unless the user chose another number.

numpy's and scipy's OpenBLAS start one thread per core when the library loads, and those
threads spin while they wait for work. A pool runs one worker per core: N workers with N
BLAS threads each oversubscribe the cores, for matrices (the orbits' Newton steps and
Floquet multipliers, core.shooting and core.floquet) far too small to gain from threads.
The tests measured it on two cores: the fast tier took 132 s of CPU under `pytest -n 2`
with OpenBLAS's default, 76 s with one thread (tests/__init__.py).

OpenBLAS reads its setting once, when it loads, and a spawned worker loads numpy before
any code of ours runs in it: while it unpickles its arguments (the options' idle hook,
slopetui.sweeps.adaptive, imports numpy). So the pool puts the setting in its own
environment before it spawns anyone, and every worker inherits it (multiprocessing's
spawn passes the parent's environment on). A user who set any of THREAD_VARIABLES keeps
the environment as it is: OpenBLAS falls back to OMP_NUM_THREADS when
OPENBLAS_NUM_THREADS is unset, so setting ours beside theirs would override their choice.
"""

from __future__ import annotations

import os
from collections.abc import MutableMapping

#: The variables that set the thread count of a BLAS or OpenMP library numpy and scipy may
#: be built with (OpenBLAS reads the first three in this order; MKL its own, then OMP's).
THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "GOTO_NUM_THREADS", "OMP_NUM_THREADS",
                    "MKL_NUM_THREADS")
#: What the workers get when the user set none of them.
ONE_THREAD = {"OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}


def one_blas_thread(environ: MutableMapping[str, str] | None = None) -> dict[str, str]:
    """Set ONE_THREAD in ``environ`` (default: this process's, which the processes it
    spawns inherit) unless a thread count is set there already (an empty value counts as
    unset, as it does for OpenBLAS). Returns what it set."""
    env = os.environ if environ is None else environ
    if any(env.get(name) for name in THREAD_VARIABLES):
        return {}
    env.update(ONE_THREAD)
    return dict(ONE_THREAD)
