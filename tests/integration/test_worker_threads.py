"""A pool's spawned workers run one BLAS thread unless the user set a thread count
(slopetui.queue.blas_threads): asked of the OpenBLAS libraries numpy and scipy loaded in
a real worker process, started by Pool._spawn as the pool starts its workers.

The worker's target lives in a module of its own, outside the tests package: a spawned
child that imports anything of ``tests`` runs tests/__init__.py, which gives the tests'
processes one BLAS thread itself and would hide what the pool passes on.
"""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path

import pytest

from slopetui.queue.blas_threads import THREAD_VARIABLES
from slopetui.queue.pool import Pool
from slopetui.queue.worker_process import WorkerOptions

#: The worker's target: its environment and the thread count of every OpenBLAS it loaded
#: (numpy's and scipy's; their get_num_threads symbols carry the build's prefix and suffix).
REPORTER = '''
import ctypes, json, os, sys

NAMES = ("openblas_get_num_threads", "openblas_get_num_threads64_",
         "scipy_openblas_get_num_threads64_", "scipy_openblas_get_num_threads")


def report(opts, stop, abort, pool_pid):
    env = {name: os.environ.get(name) for name in THREAD_VARIABLES}
    import numpy, scipy.linalg  # noqa: F401  (scipy has an OpenBLAS of its own)
    threads = {}
    with open("/proc/self/maps") as maps:
        for line in maps:
            path = line.split()[-1]
            if "openblas" in os.path.basename(path).lower() and path not in threads:
                lib = ctypes.CDLL(path)
                get = next(getattr(lib, n) for n in NAMES if hasattr(lib, n))
                threads[path] = get()
    with open(opts.log_path, "w") as out:
        json.dump({"env": env, "threads": threads}, out)
'''


@pytest.fixture
def environment():
    """No thread count set (tests/__init__.py sets one for the tests' processes), and this
    process's environment back as it was afterwards (the pool writes into it)."""
    saved = dict(os.environ)
    for name in THREAD_VARIABLES:
        os.environ.pop(name, None)
    yield os.environ
    os.environ.clear()
    os.environ.update(saved)


def worker_reports(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> dict:
    """Start one worker of a pool with the reporter as its target; what it reported."""
    (tmp_path / "blas_reporter.py").write_text(
        f"THREAD_VARIABLES = {THREAD_VARIABLES!r}\n{REPORTER}")
    monkeypatch.syspath_prepend(str(tmp_path))  # the spawned child gets this sys.path
    from blas_reporter import report

    out = tmp_path / "report.json"
    pool = Pool(WorkerOptions(db_url="sqlite://", log_path=str(out)), 1, target=report)
    pool._spawn()
    (proc,) = pool.procs.values()
    proc.join(120)
    assert proc.exitcode == 0
    sys.modules.pop("blas_reporter", None)
    return json.loads(out.read_text())


def test_a_worker_runs_one_blas_thread_by_default(environment, tmp_path, monkeypatch):
    got = worker_reports(tmp_path, monkeypatch)
    assert got["env"]["OPENBLAS_NUM_THREADS"] == "1"
    assert len(got["threads"]) >= 1 and set(got["threads"].values()) == {1}, got


def cores() -> int:
    return len(os.sched_getaffinity(0))


@pytest.mark.parametrize("name", ["OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS"])
def test_a_thread_count_the_user_set_reaches_the_worker(environment, tmp_path, monkeypatch,
                                                         name):
    """OMP_NUM_THREADS alone: OpenBLAS falls back on it, so nothing may be set beside it.
    OpenBLAS runs no more threads than cores."""
    environment[name] = "2"
    got = worker_reports(tmp_path, monkeypatch)
    assert got["env"] == {n: ("2" if n == name else None) for n in THREAD_VARIABLES}
    assert set(got["threads"].values()) == {min(2, cores())}, got
