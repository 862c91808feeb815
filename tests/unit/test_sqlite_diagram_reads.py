"""The diagram read of a SQLite file through sqlite3 (slopetui.store.diagrams.sqlite_reads,
what `slopetui show` draws from) gives what the read through SQLAlchemy gives, value for
value and type for type, and leaves every store it should not read to ``open_store``."""

from __future__ import annotations

import math
import sqlite3
from pathlib import Path
from typing import Any

import pytest

import migrations
from slopetui.queue import jobs
from slopetui.store.database import Database
from slopetui.store.diagrams.reads import read_diagram
from slopetui.store.diagrams.sqlite_reads import NeedsDatabase, read_sqlite_diagram
from slopetui.store.open import open_store
from slopetui.sweeps.control import UnknownSweep, apply
from slopetui.sweeps.diagram import load_diagram, load_drawing, read_spec
from slopetui.sweeps.spec import parse_spec
from slopetui.sweeps.submit import submit
from tests.support import QUICK_SOLVER, claim_one

PLANE = {"name": "plane", "x": {"param": "k", "start": 2, "stop": 20, "num": 4},
         "y": {"param": "tau", "start": 0.5, "stop": 10, "num": 3, "spacing": "log"},
         "solver": QUICK_SOLVER}
LINE = {"name": "line", "x": {"param": "a", "start": 0.3, "stop": 0.6, "num": 5},
        "fixed": {"tau": 2.0}, "solver": QUICK_SOLVER}


def record(i: int) -> dict[str, Any]:
    """A result with every kind of value the read decodes: NaN measurements (NULL in
    the store), peaks as JSON (none, empty, several), settled true and false, flags."""
    sliding = i % 3 == 0
    return {"regime": "sliding" if sliding else "complex", "detail": f"detail {i}",
            "lambda_max": math.nan if i % 2 else 0.01 * i, "lambda_err": math.nan,
            "amplitude": 0.0, "period": math.nan, "period_count": i,
            "maxima_per_period": None if sliding else 3, "attractor": "chaotic",
            "settled": bool(i % 2), "flags": "stiff-fallback,uphill" if i == 1 else "",
            "peaks": None if sliding else [1.5, 2.25 + i], "frequency": math.nan,
            "drift": math.nan if i == 2 else 0.125, "zero_one_k": math.nan,
            "t_blowup": None, "runtime_s": 0.5, "certified": False,
            "certificate": "not attempted", "multipliers": [], "slips": 0,
            "dt_error": math.nan, "spectrum": [], "spectrum_err": [], "t_stop": 100.0}


def fill(db: Database, sweep_id: int) -> jobs.Job:
    """Every state a run can be in: done (one of them inferred), failed, running (the
    last one, still claimed); and the run to give back to the queue once every sweep is
    filled (a run queued again would be claimed by the next fill)."""
    claimed = []
    while (job := claim_one(db, "test")) is not None:
        claimed.append(job)
    assert {job.sweep_id for job in claimed} == {sweep_id}
    for i, job in enumerate(claimed[:-3]):
        jobs.complete(db, job, "test", record(i))
    jobs.fail(db, claimed[-3], "test", "Traceback ...\nValueError: no", max_attempts=1)
    with sqlite3.connect(db.path) as conn:  # an adaptive sweep's inferred run, as stored
        conn.execute("UPDATE runs SET inferred = 1 WHERE id = ?", (claimed[0].run_id,))
    conn.close()
    return claimed[-2]


@pytest.fixture
def stored(db: Database) -> tuple[Database, int, int]:
    """A 2-D and a 1-D sweep with runs in every state."""
    plane = submit(db, parse_spec(PLANE)).sweep_id
    back = [fill(db, plane)]
    line = submit(db, parse_spec(LINE)).sweep_id
    back.append(fill(db, line))
    for job in back:
        jobs.release(db, job, "test")
    return db, plane, line


def same(a: Any, b: Any) -> bool:
    """Equal, NaN equal to NaN, and of the same type (True is not 1)."""
    if isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b):
        return True
    return type(a) is type(b) and a == b


@pytest.mark.parametrize("drawn_only", [True, False])
def test_the_sqlite_read_is_the_sqlalchemy_read(stored, drawn_only):
    db, plane, line = stored
    apply(db, "cancel", line)  # cancelled runs too
    url = db.url.render_as_string(hide_password=False)
    states = {"done", "failed", "running"}
    assert read_diagram(db, plane, read_spec).statuses.keys() == states | {"queued"}
    assert read_diagram(db, line, read_spec).statuses.keys() == states | {"cancelled"}
    for sweep in (plane, line):
        mine = read_sqlite_diagram(url, sweep, read_spec, drawn_only=drawn_only)
        theirs = read_diagram(db, sweep, read_spec, drawn_only=drawn_only)
        assert mine is not None and theirs is not None
        assert (mine.sweep_id, mine.name, mine.spec, mine.statuses, mine.max_id) == \
               (theirs.sweep_id, theirs.name, theirs.spec, theirs.statuses, theirs.max_id)
        # the SQLAlchemy read adds finished_at, last, for the live copy
        assert theirs.columns == (*mine.columns, "finished_at")
        assert len(mine.rows) == len(theirs.rows) == mine.spec.n_runs
        for a, b in zip(mine.rows, theirs.rows, strict=True):
            assert all(same(x, y) for x, y in zip(a, b[:-1], strict=True)), (a, b)
        assert abs((mine.now - theirs.now).total_seconds()) < 60
    # a drawn read of a phase diagram leaves the measurements out; a 1-D sweep's has them
    plane_read = read_sqlite_diagram(url, plane, read_spec, drawn_only=drawn_only)
    line_read = read_sqlite_diagram(url, line, read_spec, drawn_only=drawn_only)
    assert plane_read is not None and line_read is not None
    assert ("peaks" in plane_read.columns) is not drawn_only
    assert "peaks" in line_read.columns


def test_the_newest_sweep_and_sweeps_that_are_not_there(db, stored):
    _, _, line = stored
    url = db.url.render_as_string(hide_password=False)
    newest = read_sqlite_diagram(url, None, read_spec)
    assert newest is not None and newest.sweep_id == line
    assert read_sqlite_diagram(url, 99, read_spec) is None
    with pytest.raises(UnknownSweep):
        load_drawing(url, 99)


def test_a_store_without_sweeps(db):
    url = db.url.render_as_string(hide_password=False)
    assert read_sqlite_diagram(url, None, read_spec) is None
    assert load_drawing(url, None) is None


@pytest.mark.parametrize("url", ["sqlite://", "sqlite:///:memory:",
                                 "postgresql+psycopg://localhost/nothing",
                                 "sqlite+aiosqlite:///{path}", "sqlite:///{path}?timeout=5"])
def test_other_urls_go_through_the_database(db, url):
    with pytest.raises(NeedsDatabase):
        read_sqlite_diagram(url.format(path=db.path), 1, read_spec)


def test_a_missing_file_is_not_created(tmp_path: Path):
    path = tmp_path / "none.db"
    with pytest.raises(NeedsDatabase, match="no SQLite file"):
        read_sqlite_diagram(f"sqlite:///{path}", 1, read_spec)
    assert not path.exists()


def test_a_file_that_is_not_a_store(tmp_path: Path):
    path = tmp_path / "other.db"
    with sqlite3.connect(path) as conn:
        conn.execute("CREATE TABLE t (x)")
    conn.close()
    with pytest.raises(NeedsDatabase, match="sqlite3"):
        read_sqlite_diagram(f"sqlite:///{path}", 1, read_spec)
    path.write_bytes(b"not a database at all" * 100)
    with pytest.raises(NeedsDatabase, match="sqlite3"):
        read_sqlite_diagram(f"sqlite:///{path}", 1, read_spec)


def test_an_old_store_is_migrated_before_it_is_drawn(stored):
    """A store at an older schema is not read as it is: load_drawing opens it with
    open_store, which copies it aside and migrates it, then draws it."""
    from slopetui.store.migrate import downgrade, revisions

    db, plane, _ = stored
    url = db.url.render_as_string(hide_password=False)
    expected = load_diagram(db, plane, drawn_only=True)
    older = revisions()[-2]
    downgrade(db, older)
    db.dispose()
    with pytest.raises(NeedsDatabase, match=f"revision {older}, not {migrations.HEAD}"):
        read_sqlite_diagram(url, plane, read_spec)
    drawn = load_drawing(url, plane)
    assert drawn is not None
    assert [(p.id, p.status, p.regime) for p in drawn.runs] == \
           [(p.id, p.status, p.regime) for p in expected.runs]
    assert Database(url).opened_revision == migrations.HEAD
    assert list(Path(db.path).parent.glob(f"{Path(db.path).name}.bak-{older}*"))


def test_load_drawing_is_load_diagram(stored):
    """What `slopetui show` draws from a SQLite file is what it drew through SQLAlchemy."""
    db, plane, line = stored
    url = db.url.render_as_string(hide_password=False)
    for sweep in (plane, line):
        drawn = load_drawing(url, sweep)
        assert drawn is not None
        expected = load_diagram(db, sweep, drawn_only=True)
        assert (drawn.id, drawn.name, drawn.spec) == (expected.id, expected.name, expected.spec)
        for a, b in zip(drawn.runs, expected.runs, strict=True):
            assert all(same(x, y) for x, y in zip(vars(a).values(), vars(b).values(),
                                                   strict=True)), (a, b)


def test_the_store_opened_elsewhere_is_the_same(stored):
    """open_store then reads what load_drawing read (nothing was written meanwhile)."""
    db, plane, _ = stored
    url = db.url.render_as_string(hide_password=False)
    before = Path(db.path).read_bytes()
    assert load_drawing(url, plane) is not None
    assert Path(db.path).read_bytes() == before
    assert open_store(url).opened_revision == migrations.HEAD
