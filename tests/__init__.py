"""The test suite. Imported before anything else of it (conftest.py included), in every
process that runs tests (pytest-xdist's workers too), so this is where those processes,
and every process they start, get what the tests assume of their environment:

* one BLAS thread, before numpy loads OpenBLAS (which reads the setting once): OpenBLAS's
  threads spin while they wait for work, and on two cores they take the time of the
  other pytest-xdist worker and of the pools' workers, for matrices too small to gain
  from threads. Measured at load ~4 on the 2-core box: the fast tier took 132 s of CPU
  under `-n 2` with the default (2 threads), 76 s with one; serially 72 s and 63 s.
* SIGINT and SIGHUP at their defaults. The tests send them to the pools, servers and
  applications they start, and check that those stop; a suite launched in the background
  (`cmd &` in a script: SIGINT ignored) or under nohup (SIGHUP ignored) would pass the
  ignored signals on to every process it starts, which keep ignoring them, as they
  should (slopetui.queue.stop_signals): 12 of the 14 pools of test_worker_signals ran
  on past their bound, on a CI run launched as `nohup bash .ci/run &`.
"""

import os
import signal

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

if signal.getsignal(signal.SIGINT) == signal.SIG_IGN:
    signal.signal(signal.SIGINT, signal.default_int_handler)
if signal.getsignal(signal.SIGHUP) == signal.SIG_IGN:
    signal.signal(signal.SIGHUP, signal.SIG_DFL)
