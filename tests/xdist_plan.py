"""How the suite runs on several processes (pytest-xdist, `pytest -n 2`: the README's
command), as a plugin of tests/conftest.py. Without -n none of this does anything but
mark the slow tiers' group.

- The slow tiers (integration/, tui/) are one group (``--dist loadgroup`` in
  pyproject.toml): one process runs them one after another, as a plain pytest does. They
  start pools, servers, clusters and applications, and some assert how soon something
  happens: two of them at once would each get half the machine they were written for.
- The unit tier is handed out test by test to both processes; beside the group it runs at
  the lowest priority (UNIT_NICE), so that it only takes the time the group leaves. A unit
  test that asserts on wall-clock durations is marked ``wall_clock``: it joins the group,
  at full priority (tests/unit/test_estimate.py failed at UNIT_NICE in a loaded CI run: a
  sweep foretold at 1.1 s took 7.5 s).
- An integration module that only computes (no process, pool, server or application
  started, nothing timed) is marked ``computation``: it runs beside the group like the unit
  tier, at UNIT_NICE, its tests kept together in one process (its own group: they share
  module caches, e.g. test_real_crossings.py's branch walks). Measured in clean-clone
  `.ci/run`s on a quiet machine: the suite took 13 min 56 s with the ten such modules in
  the group (the group the whole of it), 10 min 55 s with them beside it.
- The controller warms the kernels up before any worker starts, as a pool does.
"""

from __future__ import annotations

import os

import pytest

#: The group name of the slow tiers (tests/conftest.py puts every test of theirs in it,
#: and the unit tests marked WALL_CLOCK).
SERIAL_GROUP = "slow-tiers"
WALL_CLOCK = "wall_clock"
COMPUTATION = "computation"
#: A process's niceness while it runs unit tests beside the group. A pool's workers run at
#: their pytest's niceness + 10 (slopetui.queue.defaults.WORKER_NICE): a unit test at the
#: group's own niceness took most of a core from them. test_hysteresis_worker.py took 147 s
#: in a `-n 2` run with the unit tests at nice 0, 17 s with them at 19 (both at load ~5,
#: with the machine's other users), 14 s in a plain run (load ~3.5).
UNIT_NICE = 19
_GROUP_HERE = pytest.StashKey[bool]()


def xdist_controller(config: pytest.Config) -> bool:
    """Whether this process hands tests out to pytest-xdist workers (`-n 2`)."""
    return (not hasattr(config, "workerinput")
            and getattr(config.option, "dist", "no") != "no"
            and bool(getattr(config.option, "tx", None)))


def pytest_configure(config: pytest.Config) -> None:
    config.addinivalue_line("markers", f"{COMPUTATION}: an integration module that only "
                            "computes: under -n 2 it runs beside the slow tiers' process "
                            "(tests/xdist_plan.py)")
    config.addinivalue_line("markers", f"{WALL_CLOCK}: asserts on wall-clock durations; "
                            "under -n 2 it runs in the slow tiers' process, at full priority "
                            "(tests/xdist_plan.py)")
    if xdist_controller(config):
        # Before the workers start: compile (or load) the kernels every pool and most
        # tests run, here, alone, and mark the cache warm, as a pool does (numba's cache
        # is not safe against two processes compiling one kernel at once; the pools the
        # tests start then only load). 0.1 s when the marker holds; 7.4 s for a cold
        # cache (measured after an engine edit at load ~3).
        from slopetui.queue.warm_up import pool_warm_up

        pool_warm_up(lambda: False)


def in_group(item: pytest.Item) -> bool:
    """Whether the test runs in the slow tiers' process (SERIAL_GROUP)."""
    return any(mark.args[:1] == (SERIAL_GROUP,) for mark in item.iter_markers("xdist_group"))


@pytest.hookimpl(trylast=True)  # after tests/conftest.py has put the slow tiers in the group
def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    # the slow tiers are here (a WALL_CLOCK unit test in the group is not slow)
    config.stash[_GROUP_HERE] = any(in_group(item) and item.get_closest_marker("slow")
                                    for item in items)


def pytest_runtest_setup(item: pytest.Item) -> None:
    """A unit test in an xdist worker of a session with the group: this process drops to
    UNIT_NICE for good (an unprivileged process cannot come back up). The process that
    runs the group takes unit tests only once its group is almost done."""
    config = item.config
    if (hasattr(config, "workerinput") and config.stash.get(_GROUP_HERE, False)
            and not in_group(item) and os.getpriority(os.PRIO_PROCESS, 0) < UNIT_NICE):
        from slopetui.queue.priority import lower_priority

        lower_priority(UNIT_NICE - os.getpriority(os.PRIO_PROCESS, 0))
