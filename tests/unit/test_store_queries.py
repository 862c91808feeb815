"""The store's named queries (slopetui.store.queries), the faces' only way to read it:
one test each, on a temporary store of each backend (SQLite, PostgreSQL: ``store``)."""

from __future__ import annotations

from datetime import UTC, datetime, timedelta

import pytest

from slopetui.store.database import Database
from slopetui.store.queries import (
    database_now,
    newest_sweep_id,
    runs_matching,
    runs_of,
    runtime_total,
    sweep_exists,
    unfinished_runs,
)
from slopetui.sweeps.spec import parse_spec
from slopetui.sweeps.submit import submit
from tests.support import QUICK_SOLVER, finish_all, submit_quick


def test_runs_matching_filters_newest_first_and_limits(store: Database):
    first = submit_quick(store, 3).sweep_id
    finish_all(store)
    second = submit_quick(store, 4, tau=3.0).sweep_id  # queued, not computed
    every = runs_matching(store)
    assert len(every) == 7
    assert [r.id for r in every] == sorted((r.id for r in every), reverse=True)
    assert {r.sweep_id for r in runs_matching(store, sweep=first)} == {first}
    assert len(runs_matching(store, sweep=second)) == 4
    assert {r.sweep_id for r in runs_matching(store, status="queued")} == {second}
    assert len(runs_matching(store, status="done")) == 3
    regime = every[-1].regime  # the oldest run: done, so it has a regime
    assert regime is not None
    matching = runs_matching(store, regime=regime)
    assert matching and all(r.regime == regime for r in matching)
    assert runs_matching(store, sweep=second, status="done") == []
    assert [r.id for r in runs_matching(store, limit=2)] == [r.id for r in every[:2]]
    assert len(runs_matching(store, limit=0)) == 7  # 0: all, as `slopetui runs --limit 0`


def test_sweep_exists(store: Database):
    sweep = submit_quick(store, 2).sweep_id
    assert sweep_exists(store, sweep)
    assert not sweep_exists(store, sweep + 1)


def test_runs_of_reads_a_sweep_in_grid_order(store: Database):
    spec = parse_spec({"x": {"param": "k", "start": 4, "stop": 12, "num": 3},
                       "y": {"param": "tau", "start": 1, "stop": 3, "num": 2},
                       "solver": QUICK_SOLVER})
    other = submit_quick(store, 2).sweep_id
    sweep = submit(store, spec).sweep_id
    runs = list(runs_of(store, sweep))
    assert [(r.iy, r.ix) for r in runs] == [(iy, ix) for iy in range(2) for ix in range(3)]
    assert {r.sweep_id for r in runs} == {sweep}
    assert len(list(runs_of(store, other))) == 2
    assert list(runs_of(store, sweep + 1)) == []  # an unknown sweep: no runs


def test_newest_sweep_id(store: Database):
    assert newest_sweep_id(store) is None
    submit_quick(store, 1)
    newest = submit_quick(store, 1, tau=3.0).sweep_id
    assert newest_sweep_id(store) == newest


def test_database_now_is_the_database_clock_in_utc(store: Database):
    now = database_now(store)
    assert isinstance(now, datetime)
    assert abs(now - datetime.now(UTC).replace(tzinfo=None)) < timedelta(minutes=1)


def test_unfinished_runs_counts_the_runs_not_done(store: Database):
    a = submit_quick(store, 3).sweep_id
    b = submit_quick(store, 2, tau=3.0).sweep_id
    assert unfinished_runs(store, [a, b]) == 5
    assert unfinished_runs(store, {"a": a}.values()) == 3  # any iterable of ids (the report's)
    finish_all(store)
    assert unfinished_runs(store, [a, b]) == 0
    assert unfinished_runs(store, []) == 0


def test_runtime_total_sums_the_runs_runtimes(store: Database):
    a = submit_quick(store, 3).sweep_id
    assert runtime_total(store, [a]) == 0.0  # queued runs have no runtime yet
    finish_all(store)
    runs = runs_matching(store, sweep=a)
    total = runtime_total(store, [a])
    assert isinstance(total, float) and total > 0
    assert total == pytest.approx(sum(r.runtime_s or 0.0 for r in runs))
    assert runtime_total(store, [a + 1]) == 0.0
