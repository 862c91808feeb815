"""What the workers' kernels cost on this store: seconds per integration step, measured
from the runs they computed.

A computed run stores ``runtime_s``: its integration time (a batched run: its share of
the batch's wall time, in proportion to its steps; core.batch) plus its classification.
Divided by its steps (t_end / dt), that is the cost a new run of the same method will
have on these workers, batched or not, on this machine: what an estimate should use.
"""

from __future__ import annotations

import statistics

from sqlalchemy import select

from slopetui.store.database import Database
from slopetui.store.models import Run

#: The newest computed runs of a method that a speed is taken from: enough that one slow
#: run (a loaded machine, a first compile) does not move the median, few enough that the
#: speed follows a change of machine or engine.
RECENT_RUNS = 200


def seconds_per_step(db: Database, method: str, lyap: bool) -> float | None:
    """The median seconds per step of the newest computed runs of ``method`` (with or
    without lambda_max); None if none was computed on this store yet. Runs copied from the
    cache, inferred runs and runs that blew up (their steps are not t_end / dt) do not
    count."""
    query = (select(Run.runtime_s, Run.t_end, Run.dt)
             .where(Run.status == "done", Run.method == method, Run.lyap.is_(lyap),
                    Run.cached_from.is_(None), Run.inferred.is_(False),
                    Run.t_blowup.is_(None), Run.runtime_s > 0)
             .order_by(Run.id.desc()).limit(RECENT_RUNS))
    with db.sessions() as s:
        costs = [runtime / (t_end / dt) for runtime, t_end, dt in s.execute(query)
                 if runtime is not None]  # the query keeps runtime_s > 0 only
    return statistics.median(costs) if costs else None
