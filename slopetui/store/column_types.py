"""Column types the models need beyond SQLAlchemy's own."""

from __future__ import annotations

import math
from typing import Any

from sqlalchemy import Double
from sqlalchemy.engine import Dialect
from sqlalchemy.types import TypeDecorator


class Measure(TypeDecorator[float]):
    """A double-precision measurement that may be NaN or +-infinity.

    PostgreSQL stores NaN and +-Infinity natively. SQLite stores +-Inf as REAL but has no
    NaN: it turns a bound NaN into NULL. slopetui never writes NULL into a measurement of a
    finished run (the engine reports "undefined" as NaN, e.g. the period of a chaotic run),
    so on SQLite a NULL measurement of a run with status 'done' *is* NaN, and it is read
    back as NaN. In SQL this keeps IEEE semantics: ``period > 0`` is false for NaN and for
    NULL alike, where a text sentinel such as 'NaN' would compare greater than any number.
    """

    impl = Double
    cache_ok = True

    def process_bind_param(self, value: Any, dialect: Dialect) -> float | None:
        return None if value is None else float(value)

    def process_result_value(self, value: Any, dialect: Dialect) -> float:
        return math.nan if value is None else float(value)
