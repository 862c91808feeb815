"""The pool's rule for its workers' BLAS threads (slopetui.queue.blas_threads): one, unless
the user set a thread count; the spawned workers themselves are in
tests/integration/test_worker_threads.py."""

from __future__ import annotations

import pytest

from slopetui.queue.blas_threads import ONE_THREAD, THREAD_VARIABLES, one_blas_thread


def test_with_no_thread_count_set_the_workers_get_one_thread():
    env = {"PATH": "/usr/bin", "OPENBLAS_NUM_THREADS": ""}  # empty: unset, for OpenBLAS too
    assert one_blas_thread(env) == ONE_THREAD
    assert env == {"PATH": "/usr/bin", **ONE_THREAD}


@pytest.mark.parametrize("name", THREAD_VARIABLES)
def test_a_thread_count_the_user_set_is_kept_and_nothing_added(name):
    """OMP_NUM_THREADS alone still sets OpenBLAS's count (its fallback): an
    OPENBLAS_NUM_THREADS=1 added beside it would override the user."""
    env = {name: "2"}
    assert one_blas_thread(env) == {}
    assert env == {name: "2"}
