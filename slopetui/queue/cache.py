"""The result cache: equal parameters, delta, solver settings and engine give equal
results (the model is deterministic), so a finished run's result is reused.

Only computed runs serve: an inferred run of an adaptive sweep (``Run.inferred``) is
done and has a cache key, but its regime is a guess from its cell's corners and it has
no measurements, so it must never stand in for a computation.
"""

from __future__ import annotations

import hashlib
from collections.abc import Iterable, Mapping
from typing import Any

from sqlalchemy import select
from sqlalchemy.orm import Session

from core import PARAM_NAMES
from core.result_fields import RESULT_NAMES
from slopetui.store.models import Run

#: The columns of Run that hold a result, in order (defined once in core.result_fields).
RESULT_FIELDS = RESULT_NAMES
#: The columns that decide a result.
KEY_FIELDS = (*PARAM_NAMES, "method", "dt", "t_end", "window", "lyap", "engine")


def cache_key(inputs: Mapping[str, Any]) -> str:
    """A hash of KEY_FIELDS; floats by repr(), which round-trips them exactly."""
    text = ";".join(f"{name}={inputs[name]!r}" for name in KEY_FIELDS)
    return hashlib.sha256(text.encode()).hexdigest()[:32]


def finished_results(session: Session, keys: Iterable[str]) -> dict[str, Run]:
    """The earliest finished, computed (not inferred) run for each of the keys that has
    one."""
    found: dict[str, Run] = {}
    keys = list(set(keys))
    for i in range(0, len(keys), 500):  # stay under SQLite's bound-parameter limit
        rows = session.scalars(select(Run).where(Run.cache_key.in_(keys[i:i + 500]),
                                                 Run.status == "done",
                                                 Run.inferred.is_(False))
                               .order_by(Run.id))
        for run in rows:
            found.setdefault(run.cache_key, run)
    return found


def result_of(run: Run) -> dict[str, Any]:
    return {name: getattr(run, name) for name in RESULT_FIELDS}
