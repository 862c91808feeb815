"""The result cache's key: equal parameters, delta, history, solver settings (the stop
rule included) and engine give equal results (the model is deterministic), so a finished run's result is reused.

Only computed runs serve: an inferred run of an adaptive sweep (``Run.inferred``) is
done and has a cache key, but its regime is a guess from its cell's corners and it has
no measurements, so it must never stand in for a computation. The lookups, which keep to
that, are the store's (``slopetui.store.runs.cached_results``).
"""

from __future__ import annotations

import hashlib
from collections.abc import Mapping
from typing import Any

from core.params import PARAM_NAMES
from core.result_fields import RESULT_NAMES

#: The columns of Run that hold a result, in order (defined once in core.result_fields).
RESULT_FIELDS = RESULT_NAMES
#: The columns that decide a result (a history "state:<digest>" names its state's
#: content, so equal names start from equal states).
KEY_FIELDS = (*PARAM_NAMES, "method", "dt", "t_end", "window", "lyap", "history", "engine")
#: The stop rule (core.solve.STOPS) under which every run before it existed ran: a run of
#: this rule keeps the key it had then, so a store's earlier results still answer.
PAPER_STOP = "t_end"


def cache_key(inputs: Mapping[str, Any]) -> str:
    """A hash of KEY_FIELDS and the stop rule (``stop``; absent: PAPER_STOP), which is part
    of the key unless it is PAPER_STOP; floats by repr(), which round-trips them exactly.
    A certified run stops early with a result a run to t_end need not share (its window
    ends at t_stop), so the two never answer for each other."""
    text = ";".join(f"{name}={inputs[name]!r}" for name in KEY_FIELDS)
    stop = inputs.get("stop", PAPER_STOP)
    if stop != PAPER_STOP:
        text += f";stop={stop!r}"
    return hashlib.sha256(text.encode()).hexdigest()[:32]
