"""A stored run computed again with the certified stop (``stop = "certified"``): a one-run
sweep at the run's point, with its solver and history, submitted as ``slopetui submit``
submits any spec (the same parser, the same admission checks, the same cache). No UI here.
"""

from __future__ import annotations

from typing import Any

from core.params import PARAM_NAMES
from slopetui.store.database import Database
from slopetui.store.queries import run_by_id
from slopetui.sweeps.spec import SpecError, SweepSpec, parse_spec
from slopetui.sweeps.submit import Submitted, submit

#: The stop rule of the re-run (core.solve.STOPS).
CERTIFIED = "certified"


def rerun_data(db: Database, run_id: int) -> dict[str, Any]:
    """The spec mapping of run ``run_id`` again with the certified stop: one point, x = k
    at the run's k (num 1), everything else fixed at the run's values; SpecError naming
    ``run`` if the store has no such run."""
    run = run_by_id(db, run_id)
    if run is None:
        raise SpecError("run", f"no run {run_id} in this store")
    return {"name": f"run {run_id} certified",
            "x": {"param": "k", "start": run.k, "stop": run.k, "num": 1},
            "fixed": {n: getattr(run, n) for n in PARAM_NAMES if n != "k"},
            "solver": {"method": run.method, "dt": run.dt, "t_end": run.t_end,
                       "window": run.window, "lyap": bool(run.lyap), "history": run.history,
                       "stop": CERTIFIED}}


def rerun_spec(db: Database, run_id: int) -> SweepSpec:
    """The one-run sweep that computes run ``run_id`` again with the certified stop,
    checked as a new sweep is (SpecError naming the field)."""
    return parse_spec(rerun_data(db, run_id), submitting=True)


def rerun_certified(db: Database, run_id: int) -> Submitted:
    """Queue run ``run_id`` again with the certified stop, as a one-run sweep."""
    return submit(db, rerun_spec(db, run_id))
