"""What a read of a sweep's diagram returns, and which run columns it reads.

Shared by the two reads of a diagram: through SQLAlchemy (``reads``: every
database, the application's live diagram) and through the standard library's sqlite3
(``sqlite_reads``: ``slopetui show`` on a SQLite file). No SQLAlchemy here, so
that the latter loads none.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from datetime import datetime
from typing import Any, Generic, TypeVar

S = TypeVar("S")

#: The columns every drawing of a run needs, by the names the rows carry (x and y, first,
#: are the sweep's parameters; a 1-D sweep's y is its iy).
DRAWN = ("id", "ix", "iy", "status", "regime", "inferred", "ic", "delta", "history")
#: The rest of a run's diagram fields: the bifurcation diagram's peaks and drift, the
#: figures' and the report's measurements.
MEASURED = ("peaks", "drift", "error", "detail", "period_count", "lambda_max", "lambda_err",
            "attractor", "flags", "maxima_per_period", "settled", "certified", "certificate")


def run_columns(y_param: str | None, drawn_only: bool) -> tuple[str, ...]:
    """The run columns a read takes, besides x and y: every diagram field, or with
    ``drawn_only`` those a drawing of a phase diagram needs (about half the read of a
    10,000-run sweep). A 1-D sweep (``y_param`` None) is read whole either way: its
    bifurcation diagram draws the runs' peaks and drift."""
    return DRAWN if drawn_only and y_param is not None else DRAWN + MEASURED


@dataclass(frozen=True)
class DiagramRead(Generic[S]):
    """A sweep and the runs a read found, as of ``now`` (database time).

    columns  : the names of the rows' values: "x", "y", then ``run_columns`` (and
               ``reads``' "finished_at", last)
    rows     : the runs (all, or those changed: ``reads``), in grid order
               (ic, iy, ix), each a sequence of values in ``columns`` order
    statuses : the sweep's runs per status (every run, not only ``rows``)
    max_id   : the sweep's highest run id, 0 if it has none
    """

    sweep_id: int
    name: str
    spec: S
    now: datetime
    columns: tuple[str, ...]
    rows: Sequence[Sequence[Any]]
    statuses: dict[str, int]
    max_id: int
