"""The batched kernels' sample arrays, kept for the next call (core.spare_buffers): an array
is written again only once nothing refers to it."""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np
import pytest

from core import spare_buffers as spare
from core.batch import simulate_batch
from core.params import Params
from core.solve import SolverSettings


@pytest.fixture(autouse=True)
def _nothing_kept() -> Iterator[None]:
    spare.release()
    yield
    spare.release()


def test_an_array_is_handed_out_again_only_once_nothing_refers_to_it() -> None:
    a = spare.sample_array((4, 3, 5))
    view = a[1].T  # as a trajectory views its lane
    b = spare.sample_array((4, 3, 5))
    assert b is not a and not np.shares_memory(a, b)
    del a
    c = spare.sample_array((4, 3, 5))
    shared = np.shares_memory(c, view)  # (pytest's assert would hold what it is given)
    assert not shared  # the view holds its array
    del view, b, c
    again = spare.sample_array((4, 3, 5))  # a free one, no new array
    assert len(spare._kept) == 3 and any(again is k for k in spare._kept)


def test_a_miss_lets_go_of_free_arrays_of_other_shapes() -> None:
    held = spare.sample_array((2, 3, 5))
    spare.sample_array((8, 3, 5))  # free once the call returns
    spare.sample_array((6, 3, 5))  # a miss: the free (8, 3, 5) goes, the held one stays
    assert sorted(k.shape for k in spare._kept) == [(2, 3, 5), (6, 3, 5)]
    assert any(held is k for k in spare._kept)


def test_kept_arrays_are_bounded() -> None:
    held = [spare.sample_array((1, 1, 5)) for _ in range(spare.KEPT + 3)]
    assert len(spare._kept) == spare.KEPT and len(held) == spare.KEPT + 3


def test_live_trajectories_keep_their_samples_through_later_batches() -> None:
    """A second batch of the same shapes while the first's trajectories are alive must not
    write over their samples; once they are dropped, the next batch reuses the arrays."""
    s = SolverSettings(t_end=40.0, window=10.0, lyap=False)
    points = [Params(k=k, tau=1.0) for k in np.linspace(6.0, 16.0, 8)]
    first = simulate_batch(points, s)
    kept = [tr.window.copy() for tr in first]
    other = simulate_batch([Params(k=k, tau=1.0) for k in np.linspace(20.0, 30.0, 8)], s)
    for a, window in zip(first, kept, strict=True):
        assert np.array_equal(a.window, window)
        assert not any(np.shares_memory(a.window, b.window) for b in other)
    arrays = {id(a.window.base) for a in first} | {id(a.window.base) for a in other}
    assert len(arrays) == 2 and arrays <= {id(k) for k in spare._kept}
    del first, kept, a
    again = simulate_batch(points, s)
    assert {id(tr.window.base) for tr in again} < arrays  # the first's array, written again
    for tr, single in zip(again, simulate_batch(points, s), strict=True):
        assert np.array_equal(tr.window, single.window)
