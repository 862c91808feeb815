"""Column types the models need beyond SQLAlchemy's own."""

from __future__ import annotations

import math
from typing import Any

from sqlalchemy import Double
from sqlalchemy.engine import Dialect
from sqlalchemy.types import TypeDecorator


class Measure(TypeDecorator[float]):
    """A double-precision measurement that may be NaN or +-infinity.

    NaN is stored as NULL, on every backend. SQLite has no NaN (it turns a bound NaN into
    NULL itself); PostgreSQL has one, but orders it above every number, so ``lambda_max >
    0`` held for the NaN of a run without a measurement: a query for chaotic runs counted
    them on PostgreSQL and not on SQLite (found when the store tests ran on both). NULL
    keeps IEEE semantics in SQL on both: ``period > 0`` is false for it, as for NaN.
    slopetui never writes NULL into a measurement of a finished run (the engine reports
    "undefined" as NaN, e.g. the period of a chaotic run), so a NULL measurement of a run
    with status 'done' *is* NaN, and it is read back as NaN. +-Infinity is stored as such
    (REAL on SQLite, double precision on PostgreSQL; it compares as IEEE says).
    """

    impl = Double
    cache_ok = True

    def process_bind_param(self, value: Any, dialect: Dialect) -> float | None:
        if value is None:
            return None
        number = float(value)
        return None if math.isnan(number) else number

    def process_result_value(self, value: Any, dialect: Dialect) -> float:
        return math.nan if value is None else float(value)
