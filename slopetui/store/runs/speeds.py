"""What the workers' kernels cost on this store: seconds per integration step, measured
from the runs they computed, per stop rule; and when this store's certified runs stopped.

A computed run stores ``runtime_s``: its integration time (a batched run: its share of
the batch's wall time, in proportion to its steps; core.batch) plus its classification
(and, stopping where certified, its certification's attempts). Divided by the steps it
took (t_stop / dt: t_end / dt for a run to t_end), that is the cost a new run of the same
method and stop rule will have on these workers, batched or not, on this machine: what
an estimate should use.
"""

from __future__ import annotations

from sqlalchemy import func, select

from slopetui.store.database import Database
from slopetui.store.models import Run

#: The newest computed runs of a method that a speed is taken from: enough that one slow
#: run (a first compile adds ~4 s to one run of 200 that take ~0.5 s each: 4 %) moves the
#: speed little, few enough that it follows a change of machine or engine.
RECENT_RUNS = 200
#: The newest certified runs whose stopping times an estimate is taken from: more than a
#: speed needs, since where runs stop varies across a plane far more than a kernel's
#: speed (the stable part of a (k, tau) plane stops near t = 1e3, its orbits later or
#: never); a 20 x 20 plane's worth and more.
RECENT_STOPS = 1000

#: A run's steps to where it stopped (t_stop), else its t_end: a run whose t_stop is
#: unknown (none of these: migration 0013 left NULL only where the run diverged) ran on.
_STOPPED_AT = func.coalesce(Run.t_stop, Run.t_end)


def _computed() -> tuple:
    """Runs a worker computed and finished here: not copied from the cache, not inferred,
    not blown up (their steps are not t_stop / dt), with a runtime."""
    return (Run.status == "done", Run.cached_from.is_(None), Run.inferred.is_(False),
            Run.t_blowup.is_(None), Run.runtime_s > 0)


def seconds_per_step(db: Database, method: str, lyap: bool, stop: str = "t_end") -> float | None:
    """The seconds per step of the newest computed runs of ``method`` (with or without
    lambda_max) under the stop rule ``stop``: their runtimes' sum over their steps' sum;
    None if none was computed on this store yet. A step is one to t_stop: a run that
    stopped where it was certified is charged for the steps it took, not for t_end's.

    A ratio of sums, not a median of ratios: a run stopped at t = 1562.5 still pays its
    analysis and certification (~0.5 s), which over its 1.6e6 steps is ~50 times a t_end
    run's cost per step, and a median over such runs priced a certified sweep 20-50 times
    too high. Times the mean steps of the same runs, the ratio of sums gives their mean
    runtime exactly."""
    query = (select(Run.runtime_s, _STOPPED_AT, Run.dt)
             .where(Run.method == method, Run.lyap.is_(lyap), Run.stop == stop, *_computed())
             .order_by(Run.id.desc()).limit(RECENT_RUNS))
    with db.sessions() as s:
        rows = [(runtime, stopped / dt) for runtime, stopped, dt in s.execute(query)
                if runtime is not None and stopped > 0]  # runtime_s > 0 in the query
    steps = sum(n for _, n in rows)
    return sum(runtime for runtime, _ in rows) / steps if steps > 0 else None


def certified_stops(db: Database) -> list[tuple[float, float, float]]:
    """(t_stop, t_end, dt) of the newest computed runs under the stop rule "certified", of
    any method: where a run stops depends on its attractor, not on the scheme. A run
    that stopped before its t_end was certified there; one with t_stop = t_end was not."""
    query = (select(Run.t_stop, Run.t_end, Run.dt)
             .where(Run.stop == "certified", Run.t_stop.is_not(None), *_computed())
             .order_by(Run.id.desc()).limit(RECENT_STOPS))
    with db.sessions() as s:
        return [(t_stop, t_end, dt) for t_stop, t_end, dt in s.execute(query)
                if t_stop is not None]  # the query keeps t_stop IS NOT NULL only
