"""Adaptive phase diagrams in the store: a sweep advances level by level as its runs
finish, whoever finishes them.

A 2-D sweep submitted with ``[adaptive] levels = L`` (``slopetui submit --adaptive L``)
queues only its coarse lattice (level 0, every ``2**L``-th point of each axis and the
last one). Each time a level is complete, ``advance`` queues the next one: the points
around the cells whose corners disagree (``slopetui.sweeps.refinement`` holds the
geometry and the argument for it). When nothing is left to refine, it writes the
*inferred* runs, one per lattice point never computed, and marks the sweep refined.
The lattice is then full: every point has exactly one run, computed or inferred.

Decisions, and why:

- *Nothing depends on the submitting process.* The state of a sweep is in the store:
  ``sweeps.level`` (the level queued last), ``sweeps.refined``, and each run's label and
  ``runs.level``. The refinement is a pure function of the labels (decisions use only
  the corners of active cells, known when their level completes), so ``advance``
  replays it from the stored labels instead of keeping cells in the database. Workers
  call ``advance_all`` after each batch and when idle; any process may call ``advance``.
- *One transaction, re-checked inside.* ``advance`` runs in one write transaction
  (BEGIN IMMEDIATE on SQLite, the sweep's row locked FOR UPDATE on PostgreSQL) and
  re-reads the condition there: two workers that both see a level complete queue the
  next one once. Calling it again, or on a sweep that is not ready, changes nothing.
  The store opens that transaction and makes the check
  (``slopetui.store.sweeps.refinement.advance_if_ready``); the step it calls back is here.
- *A level is complete when none of its runs is queued or running.* A failed run is
  complete: its label is ``failed``, so the cells around it refine (the failure is
  surrounded by computed points) and an inferred point never takes a failed label
  from a cell that also has regimes. A cell whose 4 corners all failed fills its
  points as *failed* inferred runs (status failed, inferred true, an error saying
  so): there is no regime to infer.
- *Paused and cancelled sweeps do not advance*; a resumed one advances at the next
  call (a worker's idle poll).
- *The cache.* New points take the result of an earlier computed run with the same
  cache key, exactly as at submission. A level served wholly by the cache is complete
  at once, so ``advance`` goes on to the next level in the same transaction. Inferred
  runs never serve as cache hits (``slopetui.queue.cache``).
- *Inferred runs* are status done, ``inferred`` true, ``regime`` the inferred label,
  ``level`` the level of the cell they were inferred from (a cell of level l spans
  2**(L - l) lattice steps), every measurement NULL, no worker and no timestamps but
  ``created_at``. ``cache_key`` is set as for any run (the column is NOT NULL, and a
  user may want to find the computed run of the same point later).
- *Progress.* ``sweeps.n_runs`` is the final lattice's size, so done/total reaches
  100% when the inferred runs are written; until then status says which level runs.
"""

from __future__ import annotations

import logging

from core.jit_cache import source_digest
from slopetui.store.database import Database
from slopetui.store.sweeps.refinement import LockedSweep, advance_if_ready, ready_sweeps
from slopetui.sweeps.refinement import FAILED, Point, Refinement, RefinementError
from slopetui.sweeps.run_rows import run_rows
from slopetui.sweeps.spec import SweepSpec, parse_spec

__all__ = ["FAILED_CELL_ERROR", "advance", "advance_all", "ready_sweeps"]

log = logging.getLogger("slopetui.adaptive")

#: What an inferred run of a cell whose corners all failed says in ``runs.error``.
FAILED_CELL_ERROR = "inferred, not computed: the 4 corners of its cell failed"


def advance(db: Database, sweep_id: int) -> int:
    """Queue the next level of an adaptive sweep whose current level is complete, or
    write its inferred runs when refinement is over. Returns the runs queued (0 when
    the sweep is not adaptive, not active, refined, or its level is still running).

    Raises RefinementError when the stored runs do not fit the sweep's level (a corner
    of an active cell has no computed run), which only a hand-edited store can do.
    """
    return advance_if_ready(db, sweep_id, _step)


def _step(sweep: LockedSweep) -> int:
    return _advance(sweep, parse_spec(sweep.spec))


def _advance(sweep: LockedSweep, spec: SweepSpec) -> int:
    assert spec.y is not None
    nx, ny, levels = spec.x.num, spec.y.num, sweep.levels
    labels = _known_labels(sweep)
    engine = source_digest()
    while True:
        refinement = Refinement(nx, ny, levels, labels, sweep.level)
        plan = refinement.next_level()
        if plan is None:
            _insert_inferred(sweep, spec, refinement.fill(), engine)
            sweep.mark_refined()
            return 0
        sweep.level = plan.level
        if not plan.new:
            continue  # a level with nothing to compute is complete at once
        rows = run_rows(spec, engine, plan.new)
        for row in rows:
            row["level"] = plan.level
        n_cached = sweep.insert_runs(rows)
        if n_cached < len(rows):
            return len(rows) - n_cached
        labels.update({(r["ix"], r["iy"]): str(r["regime"]) for r in rows})  # type: ignore[misc]


def _known_labels(sweep: LockedSweep) -> dict[Point, str]:
    """The label of every computed run of the sweep that finished: its regime, or
    FAILED."""
    return {(ix, iy): (str(regime) if status == "done" else FAILED)
            for ix, iy, status, regime in sweep.finished_runs()}


def _insert_inferred(sweep: LockedSweep, spec: SweepSpec,
                     fill: dict[Point, tuple[str, int]], engine: str) -> None:
    if not fill:
        return
    points = sorted(fill, key=lambda p: (p[1], p[0]))
    rows = run_rows(spec, engine, points)
    for row, point in zip(rows, points, strict=True):
        label, level = fill[point]
        row.update(sweep_id=sweep.id, inferred=True, level=level)
        if label == FAILED:
            row.update(status="failed", regime=None, error=FAILED_CELL_ERROR)
        else:
            row.update(status="done", regime=label, error=None)
    sweep.insert_inferred(rows)


def advance_all(db: Database) -> int:
    """Advance every adaptive sweep that is ready (see advance); returns the runs queued.

    Cheap when there is nothing to do (one read, no write lock), so idle workers may call
    it on every poll. A sweep whose stored runs do not fit its level is logged and
    skipped, so that it cannot stall the others.
    """
    queued = 0
    for sweep_id in ready_sweeps(db):
        try:
            queued += advance(db, sweep_id)
        except RefinementError as exc:
            log.warning("adaptive sweep %d cannot advance: %s", sweep_id, exc)
    return queued
