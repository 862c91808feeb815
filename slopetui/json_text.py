"""The one JSON encoder of slopetui's output: every ``--json`` (run, orbit, continue,
hysteresis, branch, status, submit, workers, sql) and ``export --json`` / ``runs --json``
write through ``json_text``.

**The rule for numbers that are not finite.** Strict JSON (RFC 8259) has no NaN and no
infinity, and the literals Python writes for them (``NaN``, ``Infinity``) are refused by
jq, JavaScript's ``JSON.parse`` and most other readers. A float that is NaN, ``inf`` or
``-inf`` is written as ``null``, wherever it is (a record's field, a list of peaks, a
multiplier): one type per key, a number or null, which jq compares as IEEE compares NaN
(``null > 0`` is false; the strings ``"nan"`` or ``"-inf"`` would sort above every
number). What a null stands for is said by the other keys: a run's ``status`` and
``inferred`` tell "never measured" from "measured, and the value does not exist" (the
period of a chaotic run). ±inf is null too, not ``"inf"`` (a string would give the key
two types) nor ``1e999`` (which readers take as inf, as the largest double or as an
error): its sign is lost here, and kept by the formats that have NaN and ±inf: the CSV
(``nan``, ``inf``, ``-inf``; an empty cell is a value that does not exist), Parquet and
the notebook's DataFrames. docs/outputs.md states the rule for users, with a table.

numpy's scalars and arrays are written as the Python values they hold (a ``numpy.bool_``
as true or false, an array as a list). They are recognised by the module of their type,
so that this module does not import numpy: ``slopetui status --json`` starts without it
(tests/integration/test_startup.py).
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from typing import Any


def plain(value: Any) -> Any:
    """``value`` with every non-finite float as None and numpy's values as Python's (dicts,
    lists and tuples walked); anything else as it is, for json's ``default``."""
    if isinstance(value, float):  # numpy.float64 too (a float subclass)
        return float(value) if math.isfinite(value) else None
    if value is None or isinstance(value, (str, int)):  # bool is an int
        return value
    if isinstance(value, dict):
        return {plain(k) if not isinstance(k, str) else k: plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if type(value).__module__ == "numpy" and hasattr(value, "tolist"):
        return plain(value.tolist())  # numpy.bool_, numpy.int64, arrays of any shape
    return value


def json_text(value: Any, *, ensure_ascii: bool = True,
              default: Callable[[Any], Any] | None = None) -> str:
    """``value`` as one line of strict JSON, non-finite numbers as null (see the module).

    ensure_ascii : escape every non-ASCII character (the default): text stored by anyone
                   (a sweep's name) then reaches a terminal as ``\\u...``, bidi overrides
                   and C1 controls included. False writes the text as stored, for files.
    default      : json's hook for the types JSON has no form for (``str`` for the SQL
                   console's dates and decimals); None: such a value is a TypeError.
    """
    return json.dumps(plain(value), allow_nan=False, ensure_ascii=ensure_ascii, default=default)
