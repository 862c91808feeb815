"""A run's result is defined once (core.result_fields): the table, the exporters, the
detail view and the engine agree with that definition."""

from __future__ import annotations

import io
import json
from dataclasses import fields

from sqlalchemy import JSON, Boolean, Double, Integer, String
from sqlalchemy import inspect as sa_inspect

from core.params import Params
from core.point import run_point
from core.result_fields import RECORD_KEYS, RESULT_FIELDS, RESULT_NAMES
from core.solve import SolverSettings
from slopetui.cli import main
from slopetui.queue import cache
from slopetui.store.column_types import Measure
from slopetui.store.models import Run
from slopetui.sweeps.export import write_csv
from slopetui.sweeps.recompute import StoredRun

#: The documented contract of ``slopetui run --json``: these keys first, in this order.
JSON_CONTRACT = ["regime", "lambda_max", "lambda_err", "amplitude", "period", "peaks", "drift",
                 "t_blowup", "runtime_s"]
#: The columns of runs that are not the result: inputs, the cache key, the queue.
NOT_RESULT = {"id", "sweep_id", "ix", "iy", "a", "b", "c", "d", "k", "v", "tau", "delta",
              "method", "dt", "t_end", "window", "lyap", "engine", "cache_key", "status",
              "worker_id", "attempts", "created_at", "started_at", "heartbeat_at",
              "finished_at", "error", "cached_from", "level", "inferred", "history", "ic", "stop"}
#: The SQL type of each kind of result field.
KIND_TYPES = {"measure": Measure, "count": Integer, "text": String, "list": JSON,
              "optional": Double, "flag": Boolean, "pairs": JSON}


def test_the_table_the_exporters_the_detail_view_and_the_engine_agree(db, capsys):
    # the ORM model: exactly the result fields beside the other columns, typed by kind
    orm = sa_inspect(Run).columns
    assert set(orm.keys()) - NOT_RESULT == set(RESULT_NAMES)
    for f in RESULT_FIELDS:
        column_type = orm[f.name].type
        assert isinstance(column_type, KIND_TYPES[f.kind]), (f.name, column_type)
        assert f.kind == "measure" or not isinstance(column_type, Measure), f.name
    # the migrated table (Database migrates a new store to the head revision)
    migrated = {c["name"] for c in sa_inspect(db.engine).get_columns("runs")}
    assert migrated == set(orm.keys())
    # the cache copies the result fields, in order
    assert cache.RESULT_FIELDS == RESULT_NAMES
    # the CSV header: the result fields, together and in order
    out = io.StringIO()
    write_csv([], out)
    header = out.getvalue().strip().split(",")
    start = header.index(RESULT_NAMES[0])
    assert tuple(header[start:start + len(RESULT_NAMES)]) == RESULT_NAMES
    # the detail view's copy of a run holds every result field
    assert set(RESULT_NAMES) <= {f.name for f in fields(StoredRun)}
    # the engine computes each field, then the solver's dt and t_end
    quick = SolverSettings(method="rk4", dt=0.01, t_end=200.0, window=100.0)
    record = run_point(Params(tau=2.0), quick).as_record()
    assert tuple(record) == RECORD_KEYS
    # --json: the documented contract first, then the rest of the record
    assert main(["run", "--tau", "2", "--method", "rk4", "--dt", "0.01", "--t-end", "200",
                 "--window", "100", "--json"]) == 0
    keys = list(json.loads(capsys.readouterr().out))
    assert keys[:len(JSON_CONTRACT)] == JSON_CONTRACT
    # ... then the history the run started from (an input, not a result), and what the
    # run was computed at (slopetui.provenance)
    assert keys[-4:] == ["history", "params", "solver", "engine"]
    assert sorted(keys[:-4]) == sorted(RECORD_KEYS)
