"""The test suite. Imported before anything else of it (conftest.py included), so this is
where the tests' processes, and every process they start, get one BLAS thread before
numpy loads OpenBLAS (which reads the setting once): OpenBLAS's threads spin while they
wait for work, and on two cores they take the time of the other pytest-xdist worker and
of the pools' workers, for matrices too small to gain from threads. Measured at load ~4
on the 2-core box: the fast tier took 132 s of CPU under `-n 2` with the default (2
threads), 76 s with one; serially 72 s and 63 s."""

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
