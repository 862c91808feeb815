"""The store as pandas DataFrames, for notebooks (``slopetui.open_store(url).runs()``) and
``slopetui export --parquet`` / ``--json``: the runs of a sweep with every column of the
CSV export, and the sweeps with their axes and their runs counted.

**Runs** (``runs_frame``): exactly the columns of ``export --csv``
(``slopetui.sweeps.export.COLUMNS``), in that order, one row per run, in grid order (by
sweep, then iy, then ix, then initial condition ic). The dtypes:

- ids, grid indices and ``attempts``: int64; ``iy`` is 0 on a 1-D sweep (as stored and
  as the CSV writes it), not missing;
- the columns that may be missing: nullable ``Int64`` (``cached_from``, ``level``, and
  the result counts ``period_count`` and ``maxima_per_period``) or ``boolean``
  (``settled``), with ``<NA>``;
- parameters, solver settings and the float results: float64, NaN as NaN and ±inf as
  ±inf (the store keeps NaN as NULL and reads it back as NaN, ``slopetui.store
  .column_types.Measure``; ±inf is stored as such on SQLite and PostgreSQL);
- ``lyap``, ``inferred``: bool; ``started_at``, ``finished_at``: ``datetime64[us, UTC]``
  (the store keeps UTC), NaT when missing;
- ``peaks``: Python lists (an object column), None when missing;
- text: pandas' default string dtype (``str`` with NaN for missing on pandas 3; object
  with None on pandas 2).

**Not measured vs measured and undefined.** A result exists only for a run that is done:
the results of a queued, running, failed or cancelled run are missing (NaN, <NA>, None),
and an inferred run of an adaptive sweep (``inferred`` True) has its regime and no
measurement, exactly as the CSV export writes empty cells for them. A float64 column
cannot tell that "never measured" NaN from a measured NaN (the period of a chaotic run,
``lambda_max`` of a run without Lyapunov exponents): ``status`` and ``inferred`` do. A
measurement is a value iff ``status == "done"`` and not ``inferred``
(``measured_mask``). JSON has null for both (``slopetui.json_text``): ``status`` and
``inferred`` are in every row.

**Sweeps** (``sweeps_frame``): one row per sweep, by id; ``SWEEP_COLUMNS`` says what each
column holds.

The store owns every query (``slopetui.store.runs.frames``); pandas is imported by this
module only, which the faces import when they need a DataFrame, so that ``import
slopetui`` and ``slopetui --help`` stay light.

Measured (2-core box under load, a done 100 x 100 sweep of 10 000 runs, pandas 3.1,
best and median of 7): ``runs_frame`` takes 0.17 / 0.25 s on a SQLite file and 0.24 /
0.33 s on a local PostgreSQL, most of it the read (rows of columns; the same runs as ORM
objects alone take 0.29 / 0.32 s and 0.50 / 0.60 s, before any frame is built);
``json_rows`` another 0.2 s. `slopetui export 1 --parquet -o FILE` for them: 1.6 s of
wall time, most of it imports.
"""

from __future__ import annotations

import operator
from collections.abc import Callable, Iterable, Sequence
from typing import Any, Literal

import numpy as np
import pandas as pd

from core.params import PARAM_NAMES
from core.regimes import REGIMES
from core.result_fields import BY_NAME, RESULT_NAMES
from slopetui.store.database import Database
from slopetui.store.runs.frames import run_rows, sweep_specs
from slopetui.store.statuses import RUN_STATUSES
from slopetui.sweeps.control import UnknownSweep
from slopetui.sweeps.export import COLUMNS, DERIVED, STORED, derived
from slopetui.sweeps.progress import sweep_progress

__all__ = ["COLUMNS", "SWEEP_COLUMNS", "json_rows", "measured_mask", "runs_frame",
           "sweeps_frame"]

#: How a column becomes a pandas column: int (int64), int? (Int64), float (float64), bool,
#: bool? (boolean), text, time (datetime64[us, UTC]), list (object of lists).
Kind = Literal["int", "int?", "float", "bool", "bool?", "text", "time", "list", "pairs"]

#: The result kinds of core.result_fields as frame kinds: counts and flags may be missing
#: (a run that is not done), so they are nullable.
_RESULT_KINDS: dict[str, Kind] = {"text": "text", "measure": "float", "count": "int?",
                                  "list": "list", "optional": "float", "flag": "bool?",
                                  "pairs": "pairs"}

#: The kind of every column of COLUMNS (the inputs and queue columns as the models declare
#: them: nullable where the column is).
KINDS: dict[str, Kind] = {
    "id": "int", "sweep_id": "int", "ix": "int", "iy": "int", "ic": "int",
    **{name: "float" for name in PARAM_NAMES},
    "history": "text", "method": "text", "dt": "float", "t_end": "float", "window": "float",
    "lyap": "bool", "stop": "text", "status": "text",
    **{name: _RESULT_KINDS[BY_NAME[name].kind] for name in RESULT_NAMES},
    "attempts": "int", "worker_id": "text", "cached_from": "int?", "started_at": "time",
    "finished_at": "time", "error": "text", "inferred": "bool", "level": "int?",
    "engine_version": "text", "engine_digest": "text",
}
assert set(KINDS) == set(COLUMNS), "every exported column needs a kind"

#: pandas' default dtype for text: ``str`` (missing: NaN) from pandas 3, object (None)
#: before it.
TEXT_DTYPE: Any = "str" if int(pd.__version__.split(".")[0]) >= 3 else object
#: Timestamps: the store's are UTC to the millisecond (SQLite) or microsecond (PostgreSQL).
TIME_DTYPE = "datetime64[us, UTC]"

#: The columns of ``sweeps_frame``, in order, with what they hold.
SWEEP_COLUMNS: tuple[tuple[str, str], ...] = (
    ("id", "int64: the sweep id"),
    ("name", "text"),
    ("status", "text: active, paused or cancelled as set, or done when no run is left to "
               "compute (failed if then no run is done; as `slopetui status` says)"),
    ("created_at", "datetime64[us, UTC]"),
    ("x_param", "text: the parameter along x"),
    ("x_start", "float64"), ("x_stop", "float64"), ("x_num", "int64"),
    ("x_spacing", "text: linear or log"),
    ("y_param", "text, missing for a 1-D sweep"),
    ("y_start", "float64, NaN for a 1-D sweep"), ("y_stop", "float64, NaN for a 1-D sweep"),
    ("y_num", "Int64, <NA> for a 1-D sweep"), ("y_spacing", "text, missing for a 1-D sweep"),
    ("adaptive_levels", "Int64: refinement levels of an adaptive sweep, <NA> for others"),
    ("level", "Int64: the level an adaptive sweep queued last, <NA> for others"),
    ("refined", "bool: an adaptive sweep's refinement is over (its inferred runs written)"),
    ("n_runs", "int64: runs of the whole lattice (times its initial conditions); an "
               "adaptive sweep has fewer until it is refined"),
    *((status, f"int64: runs {status}") for status in RUN_STATUSES),
    ("inferred", "int64: runs inferred, not computed (among the done ones)"),
    ("cached", "int64: done runs that took the result of an earlier identical run"),
    ("spec", "object: the stored spec as a dict (axes, fixed parameters, solver settings)"),
)

_SWEEP_KINDS: dict[str, Kind | Literal["object"]] = {
    "id": "int", "name": "text", "status": "text", "created_at": "time",
    "x_param": "text", "x_start": "float", "x_stop": "float", "x_num": "int",
    "x_spacing": "text", "y_param": "text", "y_start": "float", "y_stop": "float",
    "y_num": "int?", "y_spacing": "text", "adaptive_levels": "int?", "level": "int?",
    "refined": "bool", "n_runs": "int", **{status: "int" for status in RUN_STATUSES},
    "inferred": "int", "cached": "int", "spec": "object",
}
assert [name for name, _ in SWEEP_COLUMNS] == list(_SWEEP_KINDS)


def _series(kind: Kind | Literal["object"], values: Sequence[Any]) -> Any:
    """One column of values (None: missing) as the array of its dtype."""
    if kind == "int":
        return np.array(values, dtype=np.int64)
    if kind == "float":
        return np.array(values, dtype=np.float64)  # None -> NaN
    if kind == "bool":
        return np.array(values, dtype=bool)
    if kind == "int?":
        return pd.array(values, dtype="Int64")
    if kind == "bool?":
        return pd.array(values, dtype="boolean")
    if kind == "text":
        return pd.array(values, dtype=TEXT_DTYPE)
    if kind == "time":
        # naive datetimes in UTC (slopetui.store.db_time); None -> NaT
        return pd.array(pd.to_datetime(pd.Series(values, dtype=object))
                        .astype("datetime64[us]").dt.tz_localize("UTC"), dtype=TIME_DTYPE)
    return pd.Series(values, dtype=object).array  # lists (peaks), dicts (spec): as they are


def _frame(columns: dict[str, Any]) -> pd.DataFrame:
    return pd.DataFrame(columns, copy=False)


def measured_mask(status: Iterable[str], inferred: Iterable[bool]
                  ) -> tuple[list[bool], list[bool]]:
    """Per run: whether it has a regime (done) and whether it has measurements (done, not
    inferred). The rule of the CSV export (slopetui.sweeps.export.write_csv)."""
    done = [s == "done" for s in status]
    return done, [d and not i for d, i in zip(done, inferred, strict=True)]


def _check_filters(regime: str | None, status: str | None) -> None:
    # a typo would otherwise give an empty frame that looks like an answer
    if regime is not None and regime not in REGIMES:
        raise ValueError(f"regime = {regime!r}: allowed one of {', '.join(REGIMES)}")
    if status is not None and status not in RUN_STATUSES:
        raise ValueError(f"status = {status!r}: allowed one of {', '.join(RUN_STATUSES)}")


def runs_frame(db: Database, sweep: int | None = None, *, regime: str | None = None,
               status: str | None = None, tag: str | None = None) -> pd.DataFrame:
    """The runs of ``sweep`` (None: of every sweep) with the given regime and status, of
    the sweeps with this tag (None: any) as a DataFrame with the columns of ``COLUMNS``, dtypes and missing values
    as the module docstring says. ``regime`` selects done runs with that regime, computed
    or inferred.

    Raises UnknownSweep for a sweep id the store does not hold, ValueError for a regime
    or status that does not exist.
    """
    _check_filters(regime, status)
    if sweep is not None:
        sweep = operator.index(sweep)  # a numpy integer of a frame's id column binds as int
    rows = run_rows(db, STORED, sweep=sweep, regime=regime, status=status, tag=tag)
    if rows is None:
        assert sweep is not None
        raise UnknownSweep(sweep)
    values: dict[str, Sequence[Any]] = dict(zip(STORED, zip(*rows, strict=True), strict=True)
                                            if rows else ((c, ()) for c in STORED))
    for name in DERIVED:  # the engine's columns, from the digest stored with each run
        values[name] = [derived(name, digest) for digest in values["engine"]]
    done, measured = measured_mask(values["status"], values["inferred"])
    for name in RESULT_NAMES:  # not done (or inferred): no result yet, whatever is stored
        shown = done if name == "regime" else measured
        values[name] = [v if keep else None for v, keep in zip(values[name], shown, strict=True)]
    return _frame({name: _series(KINDS[name], values[name]) for name in COLUMNS})


def sweeps_frame(db: Database, sweep_ids: Sequence[int] | None = None) -> pd.DataFrame:
    """The sweeps (``sweep_ids``, None: all), one row each by id, with the columns of
    ``SWEEP_COLUMNS``."""
    ids = [operator.index(i) for i in sweep_ids] if sweep_ids else None
    progress = sorted(sweep_progress(db, ids), key=lambda p: p.id)
    specs = sweep_specs(db, [p.id for p in progress])
    rows: list[list[Any]] = []
    for p in progress:
        spec = specs.get(p.id, {})  # (deleted since it was counted: no axes)
        x, y = spec.get("x") or {}, spec.get("y") or {}
        rows.append([p.id, p.name, p.status, p.created_at,
                     x.get("param"), x.get("start"), x.get("stop"), x.get("num", 0),
                     x.get("spacing"), y.get("param"), y.get("start"), y.get("stop"),
                     y.get("num"), y.get("spacing"), p.adaptive_levels, p.level, p.refined,
                     p.total, *(p.counts.get(s, 0) for s in RUN_STATUSES), p.inferred,
                     p.cached, spec or None])
    names = list(_SWEEP_KINDS)
    columns = list(zip(*rows, strict=True)) if rows else [() for _ in names]
    return _frame({name: _series(_SWEEP_KINDS[name], column)
                   for name, column in zip(names, columns, strict=True)})


def _json_value(kind: Kind) -> Callable[[Any], Any]:
    """The function that turns one cell of a column of this kind into a JSON value
    (None: missing). Cells that are not measured are nulled by json_rows before; NaN
    and ±inf are nulled by the encoder (slopetui.json_text)."""
    if kind == "float":
        return float
    if kind in ("int", "int?"):
        return lambda v: None if v is pd.NA else int(v)
    if kind in ("bool", "bool?"):
        return lambda v: None if v is pd.NA else bool(v)
    if kind == "time":
        return lambda v: None if v is pd.NaT else v.isoformat()
    if kind == "list":
        return lambda v: None if v is None else [float(x) for x in v]
    if kind == "pairs":
        return lambda v: None if v is None else [[float(x), float(y)] for x, y in v]
    return lambda v: v if isinstance(v, str) else None  # text: NaN / None missing


def json_rows(frame: pd.DataFrame) -> list[dict[str, Any]]:
    """The runs of a ``runs_frame`` as JSON objects with the keys of COLUMNS, for
    ``slopetui.json_text``: missing or never measured values are None (null); a measured
    NaN or infinity stays a float, which the encoder writes as null too (its one rule for
    every JSON output); peaks is a list, timestamps ISO 8601 with their UTC offset.
    """
    done, measured = measured_mask(frame["status"].tolist(), frame["inferred"].tolist())
    columns: list[list[Any]] = []
    for name in COLUMNS:
        kind = KINDS[name]
        convert = _json_value(kind)
        cells = frame[name].tolist()
        if name in RESULT_NAMES:
            shown = done if name == "regime" else measured
            cells = [convert(v) if keep else None for v, keep in zip(cells, shown, strict=True)]
        else:
            cells = [convert(v) for v in cells]
        columns.append(cells)
    return [dict(zip(COLUMNS, row, strict=True)) for row in zip(*columns, strict=True)]
