"""Runs as flat rows: the columns of `runs --csv` and `export --csv`. The result columns
come from their one definition, core.result_fields, in its order. Each row names what the
run was computed at (slopetui.provenance): its parameters and solver settings, and, last,
its engine (``engine_version``, ``engine_digest``).

An inferred run of an adaptive sweep (``inferred`` True) has its regime and nothing
else: its measurements are empty cells (never measured), not nan (measured, undefined).
"""

from __future__ import annotations

import csv
import math
from collections.abc import Callable, Iterable
from typing import IO, TYPE_CHECKING, Any

import numpy as np

from core.params import PARAM_NAMES
from core.result_fields import RESULT_NAMES
from slopetui.json_text import json_text
from slopetui.provenance import ENGINE_COLUMNS, engine_version_of

if TYPE_CHECKING:  # only named: the figures' tables use cell() without the store's models
    from slopetui.store.models import Run

COLUMNS = ("id", "sweep_id", "ix", "iy", "ic", *PARAM_NAMES, "history", "method", "dt",
           "t_end", "window", "lyap", "stop", "status", *RESULT_NAMES, "attempts", "worker_id",
           "cached_from", "started_at", "finished_at", "error", "inferred", "level",
           *ENGINE_COLUMNS)
#: The columns that are not the store's own: the engine's, from the digest the store keeps
#: (the ``engine`` column of runs) and the version it was computed with, where known.
DERIVED: dict[str, Callable[[str | None], str | None]] = {
    "engine_version": engine_version_of, "engine_digest": lambda digest: digest}
#: The store's columns behind COLUMNS: the derived ones read from ``engine``.
STORED = (*(c for c in COLUMNS if c not in DERIVED), "engine")


def derived(name: str, engine: str | None) -> str | None:
    """A derived column's value (DERIVED) for a run computed with this engine digest."""
    return DERIVED[name](engine)


def cell(value: Any) -> Any:
    """CSV cells: NaN and infinities spelled out (nan, inf, -inf), peaks as a JSON list,
    and an empty cell only for a value that does not exist (e.g. no blow-up). numpy scalars
    and arrays (the figures' tables, slopetui.figures.output) as the Python values they hold."""
    if isinstance(value, np.ndarray):
        value = value.tolist()
    elif isinstance(value, np.generic):
        value = value.item()
    if value is None:
        return ""
    if isinstance(value, float) and not math.isfinite(value):
        return repr(value)  # 'nan', 'inf', '-inf': float() reads them back
    if isinstance(value, list):
        return json_text(value)  # the peaks: finite maxima; a NaN would be null
    return value


def write_csv(runs: Iterable[Run], out: IO[str]) -> int:
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(COLUMNS)
    n = 0
    for run in runs:
        finished = run.status == "done"  # other runs have no result yet: empty, not nan
        measured = finished and not run.inferred
        writer.writerow(["" if c in RESULT_NAMES and not (measured or (finished and c == "regime"))
                         else cell(derived(c, run.engine) if c in DERIVED else getattr(run, c))
                         for c in COLUMNS])
        n += 1
    return n
