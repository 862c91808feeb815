"""The store as DataFrames (slopetui.open_store(url).runs() / .sweeps(),
slopetui.sweeps.frames) and `slopetui export --parquet | --json`: the columns and dtypes,
NaN and ±inf kept on both backends, "never measured" told apart from a measured NaN, and
the refusals (unknown sweep, unwritable path, no pyarrow, a terminal) writing nothing."""

from __future__ import annotations

import csv
import io
import json
import math
import os
import stat
import subprocess
import sys
import threading
from pathlib import Path

import pandas as pd
import pytest
from sqlalchemy import URL, select, update

import slopetui
from core.result_fields import RESULT_NAMES
from slopetui.cli import export as export_cli
from slopetui.cli import main
from slopetui.store.database import Database
from slopetui.store.failures import StoreError
from slopetui.store.migrate import upgrade
from slopetui.store.models import Run
from slopetui.sweeps.control import UnknownSweep, cancel
from slopetui.sweeps.export import COLUMNS, DERIVED
from slopetui.sweeps.frames import KINDS, SWEEP_COLUMNS, json_rows
from slopetui.sweeps.spec import parse_spec
from slopetui.sweeps.submit import submit
from tests.support import QUICK_SOLVER, finish_all, submit_quick

#: What each run of `planted` holds in lambda_max, by ix (the last one is not done).
PLANTED = (math.nan, math.inf, -math.inf, 0.25)


def set_run(db: Database, run_id: int, **values: object) -> None:
    """Change a stored run as another tool (or an older slopetui) could have."""
    with db.transaction() as s:
        s.execute(update(Run).where(Run.id == run_id).values(**values))


def run_ids(db: Database, sweep_id: int) -> list[int]:
    with db.sessions() as s:
        return list(s.scalars(select(Run.id).where(Run.sweep_id == sweep_id).order_by(Run.ix)))


def planted(db: Database) -> int:
    """A 1-D sweep of 5 runs: 4 done with lambda_max nan, inf, -inf, 0.25, and one that
    failed with results left in its row (which are not results: it is not done)."""
    sweep = submit_quick(db, 5).sweep_id
    finish_all(db)
    ids = run_ids(db, sweep)
    for run_id, value in zip(ids, PLANTED, strict=False):
        set_run(db, run_id, lambda_max=value)
    set_run(db, ids[4], status="failed", lambda_max=1.5, error="boom")
    return sweep


def parquet_frame(data: bytes | Path) -> pd.DataFrame:
    frame = pd.read_parquet(io.BytesIO(data) if isinstance(data, bytes) else data)
    # pyarrow reads a list column back as numpy arrays
    frame["peaks"] = [None if p is None else list(p) for p in frame["peaks"]]
    return frame


def written(capsys, command: str) -> str:
    """The one line of an export to a file, on stderr; nothing on stdout."""
    captured = capsys.readouterr()
    assert captured.out == "" and command in captured.err
    return captured.err


def test_runs_keep_nan_and_infinities_through_the_store_parquet_and_json(store_url, tmp_path,
                                                                         capsys):
    with slopetui.open_store(store_url) as store:
        sweep = planted(store.database)
        frame = store.runs(sweep)
    assert tuple(frame.columns) == COLUMNS and len(frame) == 5
    lam = frame["lambda_max"]
    assert lam.dtype == "float64"
    assert math.isnan(lam[0]) and lam[1] == math.inf and lam[2] == -math.inf and lam[3] == 0.25
    assert math.isnan(lam[4]) and frame["status"][4] == "failed"  # stored 1.5: not a result
    assert frame["error"][4] == "boom" and pd.isna(frame["error"][0])
    assert frame["finished_at"].dtype == "datetime64[us, UTC]"
    assert all(isinstance(p, list) for p in frame["peaks"][:4]) and frame["peaks"][4] is None

    out = tmp_path / "runs.parquet"
    assert main(["export", str(sweep), "--parquet", "-o", str(out), "--db", store_url]) == 0
    assert "5 runs of sweep" in written(capsys, "written to")
    pd.testing.assert_frame_equal(parquet_frame(out), frame)

    out = tmp_path / "runs.json"
    assert main(["export", str(sweep), "--json", "-o", str(out), "--db", store_url]) == 0
    written(capsys, "written to")
    rows = json.loads(out.read_text(encoding="utf-8"))
    # strict JSON has no NaN nor infinity: null, as `run --json` (slopetui.json_text)
    assert [r["lambda_max"] for r in rows] == [None, None, None, 0.25, None]
    assert [list(r) for r in rows] == [list(COLUMNS)] * 5
    assert rows[4]["regime"] is None and rows[0]["regime"] is not None
    assert rows[0]["t_blowup"] is None  # no blow-up: no value, as the CSV's empty cell
    assert pd.Timestamp(rows[0]["finished_at"]) == frame["finished_at"][0]
    assert rows[0]["finished_at"].endswith("+00:00") and rows[0]["peaks"] == frame["peaks"][0]


def test_json_is_strict_and_says_what_the_csv_says(db, db_url, capsys):
    """The same cells, spelled as each format spells them: "" / null, and a measured
    nan, inf, -inf / null (the status says measured)."""
    sweep = planted(db)
    submit_quick(db, 2)  # queued runs of another sweep: not exported
    assert main(["export", str(sweep), "--csv", "--db", db_url]) == 0
    table = list(csv.DictReader(io.StringIO(capsys.readouterr().out)))
    assert main(["export", str(sweep), "--json", "--db", db_url]) == 0
    text = capsys.readouterr().out
    rows = json.loads(text, parse_constant=lambda name: pytest.fail(f"{name} in JSON"))
    assert len(rows) == len(table) == 5
    for row, line in zip(rows, table, strict=True):
        for name in COLUMNS:
            value, cell = row[name], line[name]
            if value is None:
                assert cell == "" or (cell in ("nan", "inf", "-inf") and KINDS[name] == "float"
                                      and row["status"] == "done"), (name, cell)
            elif KINDS[name] == "time":
                assert pd.Timestamp(value) == pd.Timestamp(cell, tz="UTC")
            elif isinstance(value, bool):
                assert cell == str(value)
            elif isinstance(value, list):
                assert json.loads(cell) == value
            elif isinstance(value, (int, float)):
                assert float(cell) == value, (name, cell, value)
            else:
                assert cell == value


def test_parquet_goes_to_a_pipe_and_never_to_a_terminal(db, db_url, monkeypatch, capsys):
    sweep = planted(db)
    pipe = io.TextIOWrapper(io.BytesIO(), encoding="utf-8")
    monkeypatch.setattr(sys, "stdout", pipe)
    assert main(["export", str(sweep), "--parquet", "--db", db_url]) == 0
    pipe.flush()
    frame = parquet_frame(pipe.buffer.getvalue())
    assert frame["lambda_max"].tolist()[1:3] == [math.inf, -math.inf]

    class Terminal(io.StringIO):
        def isatty(self) -> bool:
            return True

    terminal = Terminal()
    monkeypatch.setattr(sys, "stdout", terminal)
    assert main(["export", str(sweep), "--parquet", "--db", db_url]) == 2
    assert terminal.getvalue() == ""
    err = capsys.readouterr().err
    assert "--parquet writes binary data: give -o FILE" in err and len(err.splitlines()) == 1


def test_parquet_without_pyarrow_is_one_line_and_writes_nothing(db, db_url, monkeypatch,
                                                                tmp_path, capsys):
    sweep = planted(db)
    monkeypatch.setitem(sys.modules, "pyarrow", None)  # `import pyarrow` raises ImportError
    out = tmp_path / "runs.parquet"
    assert main(["export", str(sweep), "--parquet", "-o", str(out), "--db", db_url]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err == (
        "slopetui export: error: export --parquet needs pyarrow: "
        "pip install 'slopetui[parquet]'\n")
    assert not out.exists()


@pytest.mark.parametrize("form", ["--json", "--parquet"])
def test_refused_exports_write_nothing(db, db_url, tmp_path, capsys, form):
    sweep = planted(db)
    folder = tmp_path / "out"
    folder.mkdir()
    assert main(["export", "99", form, "-o", str(folder / "runs"), "--db", db_url]) == 2
    assert "SWEEP: no sweep with id 99" in capsys.readouterr().err
    targets = [folder / "missing" / "runs", folder]
    if os.geteuid() != 0:  # root writes anywhere
        read_only = folder / "read-only"
        read_only.mkdir(mode=0o500)
        targets.append(read_only / "runs")
    for target in targets:
        assert main(["export", str(sweep), form, "-o", str(target), "--db", db_url]) == 2
        err = capsys.readouterr().err
        assert f"--output: cannot write {target}" in err and len(err.splitlines()) == 1
    assert [p.name for p in folder.iterdir()] in ([], ["read-only"])
    assert not any(p for p in folder.glob("*/*"))


def test_a_failed_write_leaves_the_old_file_and_no_part(db, db_url, tmp_path, monkeypatch,
                                                        capsys):
    sweep = planted(db)
    out = tmp_path / "out" / "runs.parquet"
    out.parent.mkdir()
    out.write_bytes(b"the previous export")
    out.chmod(0o640)

    def disk_full(frame, stream):
        stream.write(b"PAR1 half a file")
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(export_cli, "_parquet", disk_full)
    assert main(["export", str(sweep), "--parquet", "-o", str(out), "--db", db_url]) == 2
    assert "No space left on device" in capsys.readouterr().err
    assert out.read_bytes() == b"the previous export"
    assert [p.name for p in out.parent.iterdir()] == ["runs.parquet"]  # no part left
    monkeypatch.undo()
    assert main(["export", str(sweep), "--parquet", "-o", str(out), "--db", db_url]) == 0
    assert len(parquet_frame(out)) == 5 and (out.stat().st_mode & 0o777) == 0o640


def test_not_done_runs_have_no_results_and_their_inputs(db):
    sweep = submit_quick(db, 3).sweep_id
    store = slopetui.Store(db)
    frame = store.runs(sweep)
    assert (frame["status"] == "queued").all() and frame["regime"].isna().all()
    assert frame["lambda_max"].isna().all() and frame["peaks"].isna().all()
    assert frame["k"].tolist() == [4.0, 8.0, 12.0] and frame["attempts"].tolist() == [0] * 3
    assert frame["period_count"].dtype == "Int64" and frame["period_count"].isna().all()
    assert frame["settled"].dtype == "boolean" and frame["started_at"].isna().all()
    rows = json_rows(frame)
    assert all(r["lambda_max"] is None and r["peaks"] is None for r in rows)


def test_dtypes_follow_the_models(db):
    """A column that may be NULL is nullable in the frame; every other one is not."""
    frame = slopetui.Store(db).runs()
    assert frame.empty and tuple(frame.columns) == COLUMNS  # the dtypes without runs too
    for name in COLUMNS:
        if name in DERIVED:  # the engine's columns: text, from the stored digest
            assert KINDS[name] == "text", name
            continue
        kind, nullable = KINDS[name], Run.__table__.c[name].nullable
        if kind in ("int", "int?", "bool", "bool?"):
            # results may be missing whatever the column allows (a run not done yet)
            assert kind.endswith("?") == (nullable or name in RESULT_NAMES), name
        expected = {"int": "int64", "int?": "Int64", "bool": "bool", "bool?": "boolean",
                    "float": "float64", "time": "datetime64[us, UTC]", "list": "object"}
        if kind in expected:
            assert str(frame[name].dtype) == expected[kind], name


def test_filters_by_sweep_regime_and_status(store):
    first = submit_quick(store, 5).sweep_id
    finish_all(store)
    second = submit_quick(store, 3, tau=3.0).sweep_id
    nb = slopetui.Store(store)
    every = nb.runs()
    assert len(every) == 8 and every["sweep_id"].tolist() == [first] * 5 + [second] * 3
    assert (nb.runs(status="queued")["sweep_id"] == second).all()
    assert len(nb.runs(second, status="done")) == 0
    regime = every["regime"][0]
    matching = nb.runs(regime=regime)
    assert len(matching) == (every["regime"] == regime).sum() > 0
    assert set(matching["regime"]) == {regime}
    with pytest.raises(UnknownSweep, match="no sweep with id 99"):
        nb.runs(99)
    with pytest.raises(ValueError, match="regime = 'chaotic': allowed one of sliding"):
        nb.runs(regime="chaotic")
    with pytest.raises(ValueError, match="status = 'complete'"):
        nb.runs(status="complete")


def test_sweeps_counts_runs_per_status(store):
    one_d = submit_quick(store, 5).sweep_id
    finish_all(store)
    spec = parse_spec({"name": "plane", "x": {"param": "k", "start": 4, "stop": 12, "num": 3},
                       "y": {"param": "tau", "start": 1, "stop": 4, "num": 2, "spacing": "log"},
                       "solver": QUICK_SOLVER})
    plane = submit(store, spec).sweep_id
    set_run(store, run_ids(store, plane)[0], status="running", worker_id="w")
    assert cancel(store, plane) == 5
    nb = slopetui.Store(store)
    sweeps = nb.sweeps()
    assert tuple(sweeps.columns) == tuple(name for name, _ in SWEEP_COLUMNS)
    assert sweeps["id"].tolist() == [one_d, plane]
    for _, row in sweeps.iterrows():
        counts = nb.runs(row["id"])["status"].value_counts()
        for status in ("queued", "running", "done", "failed", "cancelled"):
            assert row[status] == counts.get(status, 0)
    first, second = sweeps.iloc[0], sweeps.iloc[1]
    assert (first["status"], first["done"], first["n_runs"]) == ("done", 5, 5)
    assert (first["x_param"], first["x_start"], first["x_stop"], first["x_num"]) == ("k", 4, 12, 5)
    assert pd.isna(first["y_param"]) and math.isnan(first["y_start"]) and pd.isna(first["y_num"])
    assert (second["status"], second["running"], second["cancelled"]) == ("cancelled", 1, 5)
    assert (second["y_param"], second["y_num"], second["y_spacing"]) == ("tau", 2, "log")
    assert pd.isna(second["adaptive_levels"]) and not second["refined"]
    assert sweeps["created_at"].dtype == "datetime64[us, UTC]"
    assert sweeps["y_num"].dtype == "Int64" and sweeps["done"].dtype == "int64"
    assert second["spec"]["name"] == "plane"
    assert nb.sweep(plane)["n_runs"] == 6
    with pytest.raises(UnknownSweep):
        nb.sweep(99)


def test_a_1d_sweep_has_iy_0(db):
    frame = slopetui.Store(db).runs(submit_quick(db, 4).sweep_id)
    assert frame["iy"].tolist() == [0] * 4 and frame["ix"].tolist() == [0, 1, 2, 3]
    assert frame["iy"].dtype == "int64" and frame["level"].isna().all()


@pytest.mark.slow  # over 0.5 s: out of the fast loop, still in CI
def test_inferred_runs_have_their_regime_and_no_measurement(refined, capsys):
    url, sweep = refined
    with slopetui.open_store(url) as store:
        frame = store.runs(sweep)
        row = store.sweep(sweep)
    inferred = frame[frame["inferred"]]
    computed = frame[~frame["inferred"]]
    assert len(frame) == 13 * 9 and len(inferred) == row["inferred"] > 0
    assert (row["adaptive_levels"], row["refined"], row["status"]) == (2, True, "done")
    assert inferred["regime"].notna().all() and (inferred["status"] == "done").all()
    for name in ("lambda_max", "amplitude", "period", "drift", "runtime_s"):
        assert inferred[name].isna().all(), name
    assert inferred["peaks"].isna().all() and inferred["period_count"].isna().all()
    assert computed["attractor"].notna().any() and frame["level"].notna().all()
    assert main(["export", str(sweep), "--json", "--db", url]) == 0
    rows = [r for r in json.loads(capsys.readouterr().out) if r["inferred"]]
    assert len(rows) == len(inferred)
    assert all(r["regime"] and r["amplitude"] is None and r["period"] is None for r in rows)


def test_the_notebook_store(db_url, monkeypatch):
    monkeypatch.setenv("SLOPETUI_DB", db_url)
    store = slopetui.open_store()  # the default store: $SLOPETUI_DB
    assert isinstance(store, slopetui.Store) and store.url.endswith("/store.db")
    assert repr(store) == f"<slopetui.Store {store.url} (.sweeps(), .runs(sweep=ID))>"
    assert store.sweeps().empty and store.runs().empty
    with store:
        pass
    assert "closed" in repr(store)
    with pytest.raises(ValueError, match="closed"):
        store.runs()
    store.close()  # twice: nothing more


def test_import_slopetui_stays_light():
    """`import slopetui` and its version (`slopetui --help`) load no pandas, SQLAlchemy or
    numpy: open_store is imported on first use."""
    probe = ("import sys, slopetui; slopetui.__version__; "
             "print(sorted(m for m in ('pandas', 'sqlalchemy', 'numpy') if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                         check=True, timeout=60, env={**os.environ, "PYTHONPATH": os.getcwd()})
    assert out.stdout.strip() == "[]"
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        slopetui.nothing  # noqa: B018


def test_a_pipe_is_written_in_place_and_a_link_is_followed(db, db_url, tmp_path, capsys):
    """Only a file is replaced: `-o /dev/stdout` or a named pipe is written to as it is,
    and a symbolic link keeps pointing at the file it names, which is replaced."""
    sweep = planted(db)
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    got: list[bytes] = []
    reader = threading.Thread(target=lambda: got.append(fifo.read_bytes()))
    reader.start()
    assert main(["export", str(sweep), "--json", "-o", str(fifo), "--db", db_url]) == 0
    reader.join(timeout=30)
    assert len(json.loads(got[0])) == 5 and stat.S_ISFIFO(fifo.stat().st_mode)
    target, link = tmp_path / "runs.json", tmp_path / "link.json"
    target.write_text("old")
    link.symlink_to(target)
    assert main(["export", str(sweep), "--json", "-o", str(link), "--db", db_url]) == 0
    assert link.is_symlink() and len(json.loads(target.read_text())) == 5
    capsys.readouterr()


def test_a_plain_path_opens_that_sqlite_file(db, tmp_path, monkeypatch):
    """`open_store("x.db")`, a relative path, and a pathlib.Path open the SQLite file they
    name, as its sqlite:/// URL would, never the default store."""
    sweep = submit_quick(db).sweep_id
    db.dispose()
    monkeypatch.setenv("SLOPETUI_DB", f"sqlite:///{tmp_path / 'other.db'}")
    monkeypatch.chdir(tmp_path)
    for target in ("store.db", str(tmp_path / "store.db"), tmp_path / "store.db"):
        with slopetui.open_store(target) as store:
            assert store.url == f"sqlite:///{tmp_path / 'store.db'}"
            assert list(store.sweeps()["id"]) == [sweep]
    assert not (tmp_path / "other.db").exists()
    with pytest.raises(StoreError, match="store = '' is empty"):
        slopetui.open_store("")


def test_a_plain_path_with_url_syntax_in_it_opens_that_file(tmp_path, monkeypatch):
    """A path holding ?, #, %, @, : or a space names that file: none of them is read as
    the URL's query, fragment or escape."""
    monkeypatch.setenv("SLOPETUI_DB", f"sqlite:///{tmp_path / 'other.db'}")
    folder = tmp_path / "runs?v=1#x %41@h:2"
    folder.mkdir()
    target = folder / "s?mode=ro#%41.db"
    made = Database(URL.create("sqlite", database=str(target)).render_as_string(
        hide_password=False))
    upgrade(made)
    sweep = submit_quick(made).sweep_id
    made.dispose()
    for name in (target, str(target)):
        with slopetui.open_store(name) as store:
            assert list(store.sweeps()["id"]) == [sweep]
    assert not (tmp_path / "other.db").exists()
    assert [p.name for p in tmp_path.iterdir()] == [folder.name]


def test_dir_lists_the_names_loaded_on_first_use():
    """`dir(slopetui)` names open_store and Store before either is loaded (tab completion
    in a notebook reads dir)."""
    probe = ("import sys, slopetui; names = dir(slopetui); "
             "print('open_store' in names, 'Store' in names, '__version__' in names, "
             "'slopetui.notebook' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                         check=True, timeout=60, env={**os.environ, "PYTHONPATH": os.getcwd()})
    assert out.stdout.split() == ["True", "True", "True", "False"]
