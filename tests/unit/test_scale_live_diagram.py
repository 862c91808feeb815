"""A live diagram reads only what changed (the sweeps screen once re-read all of a
sweep's runs every 2 s): runs finished or inserted since the last read, and the whole
sweep again only when the runs counted per status show that something else changed."""

from __future__ import annotations

from datetime import datetime

import pytest
from sqlalchemy import update

from core.point import run_point
from slopetui.queue import jobs
from slopetui.store.models import Run
from slopetui.store.sweeps.writes import cancel_sweep, delete_sweep, resume_sweep
from slopetui.sweeps import live_diagram
from slopetui.sweeps.adaptive import advance
from slopetui.sweeps.control import UnknownSweep
from slopetui.sweeps.diagram import load_diagram
from slopetui.sweeps.live_diagram import LiveDiagram
from slopetui.sweeps.spec import parse_spec
from slopetui.sweeps.submit import submit
from tests.support import ADAPTIVE_PLANE, QUICK_SOLVER, claim_one, finish_all

LONG_AGO = datetime(2000, 1, 1)


def plane(store, nx: int = 6, ny: int = 4) -> int:
    spec = parse_spec({"x": {"param": "k", "start": 2, "stop": 20, "num": nx},
                       "y": {"param": "tau", "start": 0.5, "stop": 10, "num": ny},
                       "solver": QUICK_SOLVER})
    return submit(store, spec).sweep_id


def finish(store, n: int) -> list[int]:
    """Compute the n oldest queued runs, as a worker would; their ids."""
    ids = []
    for _ in range(n):
        job = claim_one(store, "test")
        jobs.complete(store, job, "test", run_point(job.params, job.settings).as_record())
        ids.append(job.run_id)
    return ids


def date_back(store, ids: list[int]) -> None:
    """As if the runs had finished long before (outside the re-read margin)."""
    with store.transaction() as s:
        s.execute(update(Run).where(Run.id.in_(ids)).values(finished_at=LONG_AGO))


def shown(diagram):
    return sorted((r.id, r.status, r.regime) for r in diagram.runs)


@pytest.fixture
def reads(monkeypatch):
    """The ids of the runs each read_diagram call returned, in order."""
    calls: list[set[int]] = []
    real = live_diagram.read_diagram

    def spy(*args, **kwargs):
        read = real(*args, **kwargs)
        calls.append({row.id for row in read.rows} if read is not None else set())
        return read

    monkeypatch.setattr(live_diagram, "read_diagram", spy)
    return calls


def test_a_refresh_reads_the_runs_finished_since_the_last_and_no_others(store, reads):
    sweep = plane(store)
    old = finish(store, 10)
    date_back(store, old)
    live = LiveDiagram(sweep)
    assert live.refresh(store) is True and live.whole_reads == 1
    assert len(reads[-1]) == 24  # the first read: the whole sweep
    assert live.refresh(store) is False and reads[-1] == set()  # nothing new: no row read
    new = finish(store, 5)
    assert live.refresh(store) is True
    assert reads[-1] == set(new)  # the five finished since, not the ten before
    assert shown(live.diagram) == shown(load_diagram(store, sweep))
    before = live.diagram
    # read again within the margin (a result stamped before a read may commit after it),
    # but unchanged: no new diagram
    assert live.refresh(store) is False and reads[-1] == set(new)
    assert live.diagram is before and live.whole_reads == 1


def test_a_cancel_and_a_resume_are_seen_in_the_counts_and_the_sweep_read_again(store):
    sweep = plane(store)
    finish(store, 3)
    live = LiveDiagram(sweep)
    live.refresh(store)
    cancel_sweep(store, sweep)  # queued -> cancelled: no finished_at, no new id
    assert live.refresh(store) is True and live.whole_reads == 2
    assert {r.status for r in live.diagram.runs} == {"done", "cancelled"}
    resume_sweep(store, sweep, ("cancelled",))
    assert live.refresh(store) is True and live.whole_reads == 3
    assert shown(live.diagram) == shown(load_diagram(store, sweep))


def test_a_result_the_keys_miss_is_caught_by_the_counts(store):
    sweep = plane(store)
    live = LiveDiagram(sweep)
    live.refresh(store)
    # stamped long before the last read, as a result whose transaction committed after it
    date_back(store, finish(store, 2))
    assert live.refresh(store) is True and live.whole_reads == 2
    assert sum(r.status == "done" for r in live.diagram.runs) == 2


def test_the_next_level_of_an_adaptive_sweep_is_read_by_its_new_ids(store):
    sweep = submit(store, parse_spec(ADAPTIVE_PLANE)).sweep_id
    live = LiveDiagram(sweep)
    live.refresh(store)
    assert len(live.diagram.runs) == 12  # the coarse level
    finish_all(store)
    advance(store, sweep)  # the next level's runs, inserted
    assert live.refresh(store) is True
    assert len(live.diagram.runs) > 12 and live.whole_reads == 1
    assert shown(live.diagram) == shown(load_diagram(store, sweep))
    # grid order kept for the drawings (ic, iy, ix)
    order = [(r.ic, r.iy, r.ix) for r in live.diagram.runs]
    assert order == sorted(order)


def test_a_deleted_sweep_is_unknown(store):
    sweep = plane(store)
    live = LiveDiagram(sweep)
    live.refresh(store)
    delete_sweep(store, sweep)
    with pytest.raises(UnknownSweep):
        live.refresh(store)


def test_a_grid_brought_up_to_date_with_the_changes_equals_one_made_anew(store):
    from slopetui.tui.screens.sweeps import grid_data
    from slopetui.tui.widgets.phase_grid import cell_label

    sweep = submit(store, parse_spec(ADAPTIVE_PLANE)).sweep_id  # inferred runs too, later
    live = LiveDiagram(sweep)
    live.refresh(store)
    grid = grid_data(live.diagram, None)
    for step in range(3):
        finish_all(store)
        advance(store, sweep)  # a level's runs inserted, or the inferred ones at the end
        assert live.refresh(store) is True and live.base is not None, step
        grid = grid.with_runs({(r.ix, r.iy): (r.id, cell_label(r.regime, r.status), r.inferred)
                               for r in live.changes})
        anew = grid_data(live.diagram, None)
        assert grid.runs == anew.runs and grid.inferred == anew.inferred
        assert (grid.codes == anew.codes).all()
        assert (grid.inferred_mask == anew.inferred_mask).all()
        assert grid.n_unqueued == anew.n_unqueued
    assert grid.inferred  # the refinement ended with inferred runs, put in as such
