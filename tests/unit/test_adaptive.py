"""Adaptive phase diagrams: the spec, the refinement geometry on synthetic labels, the
flow through the store (levels, inferred runs, the cache, concurrency), the migration
that adds the columns, and the drawings."""

from __future__ import annotations

import csv
import io
import random
import threading
from dataclasses import replace

import numpy as np
import pytest
from alembic import command
from sqlalchemy import func, select, text

from core.jit_cache import source_digest
from slopetui.cli import main
from slopetui.queue import jobs
from slopetui.store.database import Database
from slopetui.store.migrate import (
    alembic_config,
    current_revision,
    head_revision,
    upgrade,
)
from slopetui.store.models import Run, Sweep
from slopetui.store.open import open_store
from slopetui.store.runs.cached_results import finished_results
from slopetui.sweeps import adaptive as adaptive_module
from slopetui.sweeps import submit as submit_module
from slopetui.sweeps.adaptive import advance, advance_all, ready_sweeps
from slopetui.sweeps.diagram import load_diagram
from slopetui.sweeps.progress import sweep_progress
from slopetui.sweeps.refinement import (
    Refinement,
    RefinementError,
    axis_lines,
    coarse_points,
    refine_in_memory,
)
from slopetui.sweeps.spec import SpecError, parse_spec
from slopetui.sweeps.submit import submit
from slopetui.tui.screens.run_detail import (
    StoredRun,
    compare,
    compute_traces,
    summary_text,
)
from tests.support import ADAPTIVE_PLANE as PLANE
from tests.support import finish_adaptive, finish_all

# -- the spec ------------------------------------------------------------------------------

def plane_spec(**changes: object) -> dict:
    return {**PLANE, **changes}


@pytest.mark.parametrize("adaptive, field", [
    ({"levels": 0}, "adaptive.levels"),
    ({"levels": 9}, "adaptive.levels"),
    ({"levels": 2.5}, "adaptive.levels"),
    ({"levels": "three"}, "adaptive.levels"),
    ({}, "adaptive.levels"),
    ({"levels": 2, "halo": 1}, "adaptive.halo"),
    (3, "adaptive"),
])
def test_bad_adaptive_tables_name_their_field(adaptive, field):
    with pytest.raises(SpecError) as err:
        parse_spec(plane_spec(adaptive=adaptive))
    assert err.value.field == field


def test_a_1d_sweep_cannot_be_adaptive():
    data = {k: v for k, v in plane_spec().items() if k != "y"}
    with pytest.raises(SpecError) as err:
        parse_spec(data)
    assert err.value.field == "adaptive" and "[y]" in str(err.value)


def test_adaptive_specs_round_trip_and_count_their_coarse_runs():
    spec = parse_spec(plane_spec(x={**PLANE["x"], "num": 64}, y={**PLANE["y"], "num": 64},
                                 adaptive={"levels": "3"}))
    assert spec.adaptive_levels == 3 and parse_spec(spec.to_dict()) == spec
    # every 8th index and the last one: 0, 8, ..., 56, 63
    assert spec.first_runs == 9 * 9 and spec.n_runs == 64 * 64
    assert parse_spec({k: v for k, v in PLANE.items() if k != "adaptive"}).adaptive_levels is None


def test_submit_asks_for_yes_by_the_coarse_runs(tmp_path, capsys):
    url = f"sqlite:///{tmp_path / 's.db'}"
    big = ["submit", "--x", "k=2:20:800", "--y", "tau=0.5:10:800", "--db", url]
    assert main([*big, "--adaptive", "3"]) == 2
    assert "10201 coarse runs" in capsys.readouterr().err and not (tmp_path / "s.db").exists()
    # 100 x 100 points, of which 14 x 14 coarse: no confirmation needed
    assert main(["submit", "--x", "k=2:20:100", "--y", "tau=0.5:10:100", "--adaptive", "3",
                 "--t-end", "100", "--window", "50", "--db", url]) == 0
    assert "196 coarse runs queued" in capsys.readouterr().out


# -- the geometry on synthetic labels -------------------------------------------------------

def test_axis_lines_end_on_the_last_index_and_reach_every_index():
    lines = axis_lines(64, 3)
    assert lines[0].tolist() == [0, 8, 16, 24, 32, 40, 48, 56, 63]
    assert lines[3].tolist() == list(range(64))
    assert [ln.tolist() for ln in axis_lines(5, 3)] == [[0, 4], [0, 2, 4], [0, 1, 2, 3, 4],
                                                      [0, 1, 2, 3, 4]]


def disc(n: int, radius: float):
    c = (n - 1) / 2

    def label_of(ix: int, iy: int) -> str:
        return "inside" if (ix - c) ** 2 + (iy - c) ** 2 < radius ** 2 else "outside"
    return label_of


@pytest.mark.parametrize("n, levels", [(33, 3), (65, 4)])
def test_a_disc_is_filled_exactly_with_far_fewer_runs(n, levels):
    radius = 0.31 * n
    truth = disc(n, radius)
    result = refine_in_memory(n, n, levels, truth)
    assert len(result.labels) == n * n
    assert set(result.computed).isdisjoint(result.inferred)
    assert set(result.computed) | set(result.inferred) == set(result.labels)
    wrong = [p for p, lab in result.labels.items() if lab != truth(*p)]
    assert wrong == []
    # the cost: the coarse lattice, plus a band along the boundary about 12 points wide
    # (flagged cells of 2 steps and their halo: 6 points; the coarser levels' bands are
    # wider but sparser; a boundary crossing cells diagonally flags more of them); the
    # whole lattice would be n * n
    coarse = len(coarse_points(n, n, levels))
    assert len(result.computed) < coarse + 12 * 2 * np.pi * radius
    assert len(result.computed) < (0.7 if n == 33 else 0.4) * n * n
    # inferred points lie in uniform cells: never next to a point of the other label
    for (ix, iy), (label, _) in result.inferred.items():
        near = {truth(ix + dx, iy + dy) for dx in (-1, 0, 1) for dy in (-1, 0, 1)
                if 0 <= ix + dx < n and 0 <= iy + dy < n}
        assert near == {label}


def test_the_depth_cap_stops_a_noisy_region():
    rng = random.Random(1)
    noise = {(ix, iy): rng.choice("abc") for ix in range(33) for iy in range(33)}

    def label_of(ix: int, iy: int) -> str:
        return noise[ix, iy] if ix < 12 and iy < 12 else "a"
    result = refine_in_memory(33, 33, 3, label_of)
    assert result.level == 3  # refined to the final resolution, and no further
    assert all(0 <= lv <= 3 for lv in result.computed.values())
    noisy = [(ix, iy) for ix in range(12) for iy in range(12)]
    assert all(p in result.computed for p in noisy)  # the noise is computed, point by point
    far = [(ix, iy) for ix in range(24, 33) for iy in range(24, 33)]
    assert sum(p in result.inferred for p in far) > 0.7 * len(far)


def test_an_edge_shared_with_a_refined_neighbour_uses_computed_points_then_finer_cells():
    # 17 x 17, levels 2 (coarse lines 0, 4, 8, 12, 16). Only the corner (0..1, 0..1) is
    # "b": coarse cell [0,4]x[0,4] is flagged, its halo [0,8]x[0,8] is split. Cell
    # U = [8,12]x[0,4] stays uniform at level 0; its edge x = 8 borders the split halo cell.
    def label_of(ix: int, iy: int) -> str:
        return "b" if ix <= 1 and iy <= 1 else "a"
    result = refine_in_memory(17, 17, 2, label_of)
    assert {(8, 0), (8, 4)} <= set(result.computed) and result.computed[8, 2] == 1
    assert result.inferred[8, 1] == ("a", 1)   # from the refined neighbour's level-1 cell
    assert result.inferred[8, 3] == ("a", 1)
    assert result.inferred[10, 1] == ("a", 0)  # interior of U: U's own label
    assert all((ix, iy) in result.computed for ix in range(5) for iy in range(5))
    assert all(lab == label_of(*p) for p, lab in result.labels.items())


def test_the_halo_follows_a_boundary_out_of_the_refined_region():
    # 33 x 33 at levels 3 (coarse lines every 8). A "b" strip along x = 0..1 flags the
    # coarse cell [0,8]x[0,8]; a tongue on rows 5-6 (between the lines of levels 0 and 1)
    # leaves it to x = 10. Levels 0 and 1 split only x <= 8 (the flagged cells and their
    # halo); level 2 sees the tongue up to x = 8, and its halo, a level-2 cell of an
    # unsplit coarse cell whose corners were never computed, carries refinement to x = 10.
    def label_of(ix: int, iy: int) -> str:
        return "b" if (ix <= 1 and iy <= 8) or (iy in (5, 6) and ix <= 10) else "a"
    result = refine_in_memory(33, 33, 3, label_of)
    assert result.computed[10, 6] == 3 and result.computed[10, 5] == 3
    assert [p for p, lab in result.labels.items() if lab != label_of(*p)] == []


def test_fill_needs_a_complete_level():
    known = {p: "a" for p in coarse_points(9, 9, 2)}
    del known[4, 4]
    with pytest.raises(RefinementError, match="not complete"):
        Refinement(9, 9, 2, known, 0).next_level()


# -- through the store -----------------------------------------------------------------------

def rows(db: Database, sweep_id: int) -> list[Run]:
    with db.sessions() as s:
        return list(s.scalars(select(Run).where(Run.sweep_id == sweep_id)))


def test_every_lattice_point_ends_with_exactly_one_run(refined):
    url, sweep_id = refined
    db = open_store(url)
    runs = rows(db, sweep_id)
    assert sorted((r.ix, r.iy) for r in runs) == [(ix, iy) for ix in range(13) for iy in range(9)]
    inferred = [r for r in runs if r.inferred]
    computed = [r for r in runs if not r.inferred]
    assert inferred and computed
    assert all(r.status == "done" and r.regime and r.level is not None for r in inferred)
    assert all(np.isnan(r.lambda_max) and np.isnan(r.amplitude) and r.peaks is None
               and r.worker_id is None and r.finished_at is None for r in inferred)
    assert all(r.status == "done" and r.runtime_s is not None for r in computed)
    with db.sessions() as s:
        sweep = s.get(Sweep, sweep_id)
        assert sweep.refined and sweep.level <= 2 and sweep.n_runs == 13 * 9


def test_the_store_refines_as_the_pure_geometry_does(refined):
    url, sweep_id = refined
    runs = rows(open_store(url), sweep_id)
    computed = {(r.ix, r.iy): r.regime for r in runs if not r.inferred}
    # label_of raises KeyError on a point the store did not compute
    expected = refine_in_memory(13, 9, 2, lambda ix, iy: computed[ix, iy])
    assert set(expected.computed) == set(computed)
    assert {(r.ix, r.iy): r.level for r in runs if not r.inferred} == expected.computed
    assert {(r.ix, r.iy): r.regime for r in runs} == expected.labels


def test_advance_is_idempotent(refined):
    url, sweep_id = refined
    db = open_store(url)
    before = [(r.id, r.status, r.regime, r.inferred) for r in rows(db, sweep_id)]
    assert advance(db, sweep_id) == 0 and advance(db, sweep_id) == 0
    assert advance_all(db) == 0 and ready_sweeps(db) == []
    assert [(r.id, r.status, r.regime, r.inferred) for r in rows(db, sweep_id)] == before


def test_two_workers_advancing_at_once_queue_a_level_once(db_url):
    db = open_store(db_url)
    sweep_id = submit(db, parse_spec(PLANE)).sweep_id
    finish_all(db)
    assert ready_sweeps(db) == [sweep_id]
    results: list[int] = []
    barrier = threading.Barrier(2)

    def worker() -> None:
        other = open_store(db_url)
        barrier.wait()
        results.append(advance(other, sweep_id))
        other.dispose()
    threads = [threading.Thread(target=worker) for _ in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert min(results) == 0 and max(results) > 0
    with db.sessions() as s:
        n, distinct = s.execute(select(func.count(), func.count(func.distinct(
            Run.ix * 1000 + Run.iy))).where(Run.sweep_id == sweep_id)).one()
        assert n == distinct == 12 + results[0] + results[1]
        assert s.get(Sweep, sweep_id).level == 1


def test_progress_says_the_level_until_refined(db_url):
    db = open_store(db_url)
    sweep_id = submit(db, parse_spec(PLANE)).sweep_id
    finish_all(db)  # level 0 done, level 1 not queued yet: not "done"
    p = sweep_progress(db, [sweep_id])[0]
    assert (p.status, p.stage, p.total, p.done) == ("active", "level 0/2", 13 * 9, 12)
    finish_adaptive(db, sweep_id)
    p = sweep_progress(db, [sweep_id])[0]
    assert p.status == "done" and p.stage == "refined" and p.done == 13 * 9
    assert p.inferred > 0 and p.computed + p.inferred == 13 * 9


def test_a_paused_sweep_does_not_advance(db_url):
    db = open_store(db_url)
    sweep_id = submit(db, parse_spec(PLANE)).sweep_id
    finish_all(db)
    with db.transaction() as s:
        s.get(Sweep, sweep_id).status = "paused"
    assert ready_sweeps(db) == [] and advance(db, sweep_id) == 0


def test_an_inferred_run_is_never_a_cache_hit(db, monkeypatch):
    # one engine for both sweeps, even if core/ changes meanwhile (the key includes it)
    for module in (submit_module, adaptive_module):
        monkeypatch.setattr(module, "source_digest", lambda: "test-engine")
    # the worker's too: it writes its own engine with each result (queue.jobs.complete)
    monkeypatch.setattr(jobs, "engine_digest", lambda: "test-engine")
    sweep_id = submit(db, parse_spec(PLANE)).sweep_id
    finish_adaptive(db, sweep_id)
    runs = rows(db, sweep_id)
    # the same plane, every point computed: computed points come from the cache only
    out = submit(db, parse_spec({k: v for k, v in PLANE.items() if k != "adaptive"}))
    assert out.n_cached == sum(not r.inferred for r in runs)
    with db.sessions() as s:
        again = {(r.ix, r.iy): r for r in s.scalars(select(Run).where(
            Run.sweep_id == out.sweep_id))}
    for r in runs:
        copy = again[r.ix, r.iy]
        if r.inferred:
            assert (copy.status, copy.cached_from) == ("queued", None)
        else:
            assert (copy.status, copy.cached_from) == ("done", r.id)


def test_show_draws_an_adaptive_sweep_with_its_counts(refined, capsys):
    url, sweep_id = refined
    diagram = load_diagram(open_store(url), sweep_id)
    assert diagram.n_inferred > 0 and diagram.n_computed + diagram.n_inferred == 13 * 9
    assert main(["show", str(sweep_id), "--width", "80", "--height", "24", "--color",
                 "never", "--db", url]) == 0
    out = capsys.readouterr().out
    assert f"{diagram.n_computed:,} computed, {diagram.n_inferred:,} inferred" in out
    assert f"({13 * 9}/{13 * 9} done)" in out and "pending" not in out


def test_show_draws_the_levels_to_come_as_pending(db_url, capsys):
    db = open_store(db_url)
    sweep_id = submit(db, parse_spec(PLANE)).sweep_id
    assert main(["show", str(sweep_id), "--width", "80", "--height", "24", "--color",
                 "never", "--db", db_url]) == 0
    out = capsys.readouterr().out
    assert f"pending ({13 * 9})" in out and "0 computed, 0 inferred" in out


def test_exports_and_listings_mark_inferred_runs(refined, capsys):
    url, sweep_id = refined
    assert main(["export", str(sweep_id), "--csv", "--db", url]) == 0
    exported = list(csv.DictReader(io.StringIO(capsys.readouterr().out)))
    inferred = [r for r in exported if r["inferred"] == "True"]
    assert inferred and len(exported) == 13 * 9
    # the regime, and no measurement: empty cells (never measured), not nan (undefined)
    assert all(r["regime"] and r["lambda_max"] == "" and r["drift"] == "" for r in inferred)
    assert all(r["level"] != "" for r in exported)
    assert main(["runs", "--sweep", str(sweep_id), "--limit", "0", "--db", url]) == 0
    listed = capsys.readouterr().out.splitlines()[1:]
    assert sum(line.split()[2] == "inferred" for line in listed) == len(inferred)


def test_the_run_detail_says_an_inferred_run_was_not_computed(refined):
    url, sweep_id = refined
    with open_store(url).sessions() as s:
        run = StoredRun.of(s.scalars(select(Run).where(Run.sweep_id == sweep_id,
                                                       Run.inferred)).first())
    text_ = summary_text(run)
    assert f"inferred {run.regime}, not computed" in text_ and "r computes" in text_
    verdict = compare(run, compute_traces(*run.inputs()), source_digest())
    assert verdict.text.startswith("computed:") and "inferred regime" in verdict.text
    wrong = replace(run, regime="unstable" if run.regime != "unstable" else "sliding")
    verdict = compare(wrong, compute_traces(*run.inputs()), source_digest())
    assert not verdict.ok and "the inferred regime was" in verdict.text


# -- the migration -------------------------------------------------------------------------

def test_a_0001_database_upgrades_and_keeps_its_runs(db_url):
    db = Database(db_url)
    command.upgrade(alembic_config(db), "0001")
    assert current_revision(db) == "0001"
    with db.engine.begin() as conn:
        conn.execute(text("INSERT INTO sweeps (name, spec, x_param, n_runs, status) "
                          "VALUES ('old', '{}', 'k', 1, 'active')"))
        conn.execute(text(
            "INSERT INTO runs (sweep_id, ix, iy, a, b, c, d, k, v, tau, delta, method, dt, "
            "t_end, window, lyap, engine, cache_key, status, attempts, regime) VALUES "
            "(1, 0, 0, 3.2, 7.2, 4.8, 1e-4, 10, 0.1, 10, 0.1, 'rk4', 0.01, 200, 100, 1, "
            "'e', 'key', 'done', 1, 'sliding')"))
    assert upgrade(db) == ("0001", head_revision())
    with db.sessions() as s:
        run = s.scalars(select(Run)).one()
        sweep = s.scalars(select(Sweep)).one()
        assert finished_results(s, ["key"])["key"].id == run.id  # still a cache hit
    assert (run.regime, run.inferred, run.level) == ("sliding", False, None)
    assert (sweep.adaptive_levels, sweep.level, sweep.refined) == (None, None, False)
