"""Curves in two parameters as jobs (slopetui.queue.curve_jobs, slopetui.store.jobs.curves):
the lease guards every write, points are saved in order, a finished curve keeps its
codimension-two points, a hand-edited row fails at its claim with the column named, and a
downgrade says what it drops."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from sqlalchemy import update

from core.curve_start import CurveSpec
from core.params import Params
from slopetui.queue import curve_jobs
from slopetui.store.jobs import curves
from slopetui.store.models import Curve
from slopetui.sweeps.curves import curve_of

SPEC = CurveSpec(Params(tau=2.0), "k", "tau", "fold", 0.01, 1.5, 6, 0.2)


def _point(idx: int) -> dict[str, Any]:
    return {"idx": idx, "first": 6.0 + idx, "second": 2.0 - 0.1 * idx, "period": 2.7,
            "amplitude": 1.3, "l1": None, "curvature": 14.0,
            "multipliers": [[1.0, 0.0], [0.999, 0.0], [0.5, 0.1]], "flow_index": 0,
            "translation": 1.0, "newton_steps": 2, "step": 0.1,
            "state": np.zeros(8).tobytes()}


def test_points_are_saved_by_the_lease_holder_only_and_in_order(store):
    cid = curve_jobs.submit(store, SPEC)
    assert curves.claim(store, "w1").id == cid
    assert curves.claim(store, "w2") is None  # one holder
    assert curves.save_point(store, cid, "w1", _point(0), 0.1)
    assert not curves.save_point(store, cid, "w1", _point(0), 0.1)  # not the next one
    assert not curves.save_point(store, cid, "w1", _point(2), 0.1)  # a gap
    assert not curves.save_point(store, cid, "w2", _point(1), 0.1)  # not the holder
    assert curves.save_point(store, cid, "w1", _point(1), 0.2)
    row = curves.curve(store, cid)
    assert (row.n_points, row.attempts, row.kind, row.param2) == (2, 1, "fold", "tau")
    assert row.runtime_s == pytest.approx(0.3)
    assert curves.finish(store, cid, "w1", "reached tau = 1.5", 0.0, [
        {"type": "cusp", "first": 6.5, "second": 1.95, "period": 2.7, "note": "a note"}])
    stored = curve_of(store, cid)
    assert stored is not None and stored.row.status == "done"
    assert [p["k"] for p in stored.points] == [6.0, 7.0]
    # the largest multiplier but the flow's and the fold's (the one nearest +1)
    assert stored.points[0]["leading_multiplier"] == [0.5, 0.1]
    assert stored.bifurcations == [{"type": "cusp", "k": 6.5, "tau": 1.95, "period": 2.7,
                                    "note": "a note"}]
    assert not curves.finish(store, cid, "w2", "x", 0.0, [])  # not the holder: nothing


def test_a_saved_point_reads_back_as_it_was_computed(store):
    cid = curve_jobs.submit(store, SPEC)
    curves.claim(store, "w1")
    assert curves.save_point(store, cid, "w1", _point(0), 0.1)
    (row,) = curves.saved_points(store, cid)
    saved = curve_jobs.saved_of(row)
    assert saved.first == 6.0 and saved.curvature == 14.0 and saved.newton_steps == 2
    assert saved.multipliers is not None and saved.multipliers.flow_index == 0
    np.testing.assert_array_equal(saved.state, np.zeros(8))
    again = curve_jobs.point_fields(0, saved)
    assert again == _point(0)


@pytest.mark.parametrize(("column", "value", "field"), [
    ("param", "q", "param"), ("param2", "q", "param2"), ("dt", 0.0, "dt"),
    ("end_value", -1.0, "tau"), ("max_step", 0.0, "max_step"), ("max_points", 1, "max_points"),
])
def test_a_hand_edited_row_fails_at_its_claim_naming_the_column(store, column, value, field):
    cid = curve_jobs.submit(store, SPEC)
    with store.transaction() as s:
        s.execute(update(Curve).where(Curve.id == cid).values({column: value}))
    assert curve_jobs.claim(store, "w1") is None
    row = curves.curve(store, cid)
    assert row.status == "failed" and field in row.error


def test_a_queued_spec_comes_back_as_it_was_asked(store):
    curve_jobs.submit(store, SPEC)
    assert curve_jobs.claim(store, "w1").spec == SPEC
