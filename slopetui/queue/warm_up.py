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

After its warm-up the pool prunes the kernel folders of other engine versions that nobody
uses (core.jit_cache.prune): its own engine's folder is then complete, and it is the one
place that runs once per start of a long-lived process, not once per command.

Each worker then loads every kernel at its start, before it registers, though numba would
load a kernel from the cache at its first call anyway. Measured on the 2-core machine (a
pool of one worker with --exit-when-idle, the worker's CPU from spawn to exit, from
RUSAGE_CHILDREN; eager, then lazy): on an empty queue 1.3-1.6 s, 0.4-0.6 s; with two
Euler runs to compute 1.4 s, 1.1-1.3 s; with eight (one batch) 1.5 s, 1.2-1.3 s. Lazy
loading saves 0.2-0.3 s a worker that claims anything, but its first claim's load counts
as computation in the runtime_s the store keeps: the first of two runs read 0.34-0.46 s
instead of 0.002 s, each run of the batch 0.05-0.08 s instead of 0.001-0.015 s. So the
load stays eager; with it, a broken installation or cache also kills the worker at its
start (the pool's crash-loop rule) instead of charging attempts to runs.
"""

from __future__ import annotations

import logging
import sys
import threading
import time
from collections.abc import Callable
from pathlib import Path

from core import jit_cache

log = logging.getLogger("slopetui.worker")

#: How often the waiting thread looks at the stop (s).
TICK_S = 0.2
#: A warm-up longer than this is a compilation, not a load from numba's cache (~1 s, 2-3 s
#: on a loaded machine) (s). A cold compilation of every kernel took 19-20 s on the 2-core
#: development machine (warm_up() into an empty $SLOPETUI_KERNEL_CACHE), more on a busy
#: one: the message names no figure, and the time it took is logged when it is done.
COMPILING_AFTER_S = 5.0
#: What a pool says once its warm-up turns out to be a compilation.
COMPILING = ("compiling the numba kernels, once (first run after an install or an engine "
             "change; cached afterwards)")


#: The kernels of the orbit analyses (``slopetui orbit``, ``continue``, ``hysteresis``), by
#: their module in core: every one of them integrates with core.period_map.flow (eqs.
#: 6a-6e and their tangent, into which numba compiles core.model's functions too). A
#: cold `slopetui orbit` compiled exactly these: period_map.flow and core.model's eight.
ANALYSIS_KERNELS = ("period_map",)
#: What an analysis command says on stderr before it compiles them (``say_if_compiling``).
COMPILING_ONCE = ("compiling kernels (once: the first analysis after an install or an "
                  "engine change; cached afterwards)")


def kernels_compiled(modules: tuple[str, ...] = ANALYSIS_KERNELS) -> bool:
    """Whether numba's cache holds a compiled kernel of each ``core.<module>`` for this
    checkout of the engine: an index file ``<module>.<function>-<line>.py<version>.nbi``
    in the sub-folder numba files core's kernels under (named after core's path, so
    another checkout's kernels, which this one would compile again, do not count). Only
    looks for files: an index numba finds stale (another CPU, another numba) still
    counts, and the compilation then goes unannounced, as before."""
    from numba.core.caching import _CacheLocator  # numba's own naming of the sub-folder

    folder = jit_cache.kernel_folder() / _CacheLocator.get_suitable_cache_subpath(
        str(jit_cache.CORE_DIR / "__init__.py"))
    return all(any(Path(folder).glob(f"{module}.*.nbi")) for module in modules)


def say_if_compiling(command: str, modules: tuple[str, ...] = ANALYSIS_KERNELS) -> None:
    """Say COMPILING_ONCE on stderr, as ``slopetui <command>: ...``, unless the kernels
    of ``modules`` are compiled already (``kernels_compiled``): a silent pause of seconds
    before the first line looks like a hang. Call it before the first kernel runs."""
    if not kernels_compiled(modules):
        print(f"slopetui {command}: {COMPILING_ONCE}", file=sys.stderr, flush=True)


def warm_up() -> None:
    """Compile (or load from numba's cache) every kernel a run can use, with a short run
    of each method, so the first real job does not pay for compilation."""
    from core.batch import MIN_LANES
    from core.params import Params
    from core.point import run_batch, run_point
    from core.solve import SolverSettings
    # stiff: the fallback of every explicit run that blows up (core.point)
    for method in ("euler", "rk4", "stiff"):
        settings = SolverSettings(method=method, t_end=20.0, window=10.0)
        run_point(Params(tau=1.0), settings)
        # MIN_LANES points of one tau: the batched kernel (core.batch). Fewer, or points of
        # several taus, go through the single-run kernel one by one, and the batched one
        # would first be compiled by the workers, all at once, at their first batch.
        run_batch([Params(tau=1.0, k=4.0 + i) for i in range(MIN_LANES)], settings)


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
            log.info("%s", COMPILING)
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
        prune_old_kernels()
        return checked
    took = watched_warm_up(stopped)
    if took is not None:
        jit_cache.mark_warm()
        prune_old_kernels()
    return took


def prune_old_kernels() -> None:
    """core.jit_cache.prune, logged; a failure is only logged (a courtesy: it never stops
    a pool)."""
    try:
        removed = jit_cache.prune()
    except Exception as exc:
        log.warning("could not prune old kernel folders in %s: %s", jit_cache.cache_base(), exc)
        return
    if removed:
        log.info("removed %d kernel folders of other engine versions that nobody used for "
                 "%g h, in %s", len(removed), jit_cache.PRUNE_IDLE_S / 3600,
                 jit_cache.cache_base())
