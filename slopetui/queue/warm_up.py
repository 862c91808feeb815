"""The warm-up of a pool: compile (or load from numba's cache) every kernel before any
worker starts, in a thread the caller can abandon on a stop.

The pool warms up once, serially, before it spawns anyone: several processes compiling
into one cache at once can corrupt it (numba#10128). Each worker warms up again, which
then only loads what the pool compiled. Once its warm-up is done, the pool marks the cache
complete (core.jit_cache.mark_warm); a later pool that finds the marker still true
(core.jit_cache.warmed: the same files, interpreter, numba and CPU) skips its own warm-up,
which would only have loaded, and its workers load the kernels at once. A cache that
changed since (an engine edit, a kernel compiled for a new signature) or never was
marked gets the serial warm-up, as before.
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable

from core import jit_cache

log = logging.getLogger("slopetui.worker")

#: How often the waiting thread looks at the stop (s).
TICK_S = 0.2
#: A warm-up longer than this is a compilation (~30 s), not a load from numba's cache
#: (~1 s, 2-3 s on a loaded machine) (s).
COMPILING_AFTER_S = 5.0


def warm_up() -> None:
    """Compile (or load from numba's cache) every kernel a run can use, with a short run
    of each method, so the first real job does not pay for compilation."""
    from core import Params, SolverSettings, run_batch, run_point
    # stiff: the fallback of every explicit run that blows up (core.point)
    for method in ("euler", "rk4", "stiff"):
        settings = SolverSettings(method=method, t_end=20.0, window=10.0)
        run_point(Params(tau=1.0), settings)
        run_batch([Params(tau=1.0), Params(tau=2.0)], settings)


def watched_warm_up(stopped: Callable[[], bool], announce: bool = True) -> float | None:
    """warm_up() in a daemon thread, so that this (main) thread can still act on a stop.
    ``announce``: log how long it took, and say so when it turns out to be a compilation
    (the pool; its workers then load what it compiled). Returns the seconds it took, or
    None if ``stopped()`` came first (the caller then exits; the thread dies with the
    process)."""
    errors: list[BaseException] = []

    def target() -> None:
        try:
            warm_up()
        except BaseException as exc:  # re-raised in the main thread
            errors.append(exc)

    t0 = time.monotonic()
    thread = threading.Thread(target=target, name="warm-up", daemon=True)
    thread.start()
    said = False
    while thread.is_alive():
        thread.join(TICK_S)
        if stopped():
            return None
        if announce and not said and time.monotonic() - t0 > COMPILING_AFTER_S:
            log.info("compiling the numba kernels (first run after install or an engine "
                     "change; ~30 s)")
            said = True
    if errors:
        raise errors[0]
    took = time.monotonic() - t0
    if said:
        log.info("numba kernels compiled in %.1f s", took)
    elif announce:
        log.info("numba kernels loaded from numba's cache in %.1f s", took)
    return took


def pool_warm_up(stopped: Callable[[], bool]) -> float | None:
    """The pool's warm-up, before it spawns its workers: none if a previous one's marker is
    still true (core.jit_cache.warmed; the workers' warm-ups then only load), else
    watched_warm_up(stopped), after which the marker is written. Returns the seconds it
    took (the check's when skipped), or None if ``stopped()`` came first."""
    t0 = time.monotonic()
    if jit_cache.warmed():
        checked = time.monotonic() - t0
        log.info("numba's cache holds every kernel (checked in %.2f s): the workers load "
                 "them", checked)
        return checked
    took = watched_warm_up(stopped)
    if took is not None:
        jit_cache.mark_warm()
    return took
