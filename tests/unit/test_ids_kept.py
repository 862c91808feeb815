"""Ids keep their meaning: a sweep, run, continuation or hysteresis
sweep id is never handed out twice, on SQLite (AUTOINCREMENT, migration 0009) as on
PostgreSQL (sequences); and migration 0009 keeps every row, index, foreign key and named
constraint of a store at 0008, there and back."""

from __future__ import annotations

import math
from typing import Any

import pytest
from alembic import command
from sqlalchemy import inspect, text

from slopetui.queue import branch_jobs, hysteresis_jobs
from slopetui.store.database import Database
from slopetui.store.integrity import integrity_problems
from slopetui.store.jobs import continuations
from slopetui.store.migrate import alembic_config, current_revision, downgrade, upgrade
from slopetui.store.models import Base
from slopetui.sweeps import control
from tests.support import finish_all, submit_quick
from tests.unit.test_branch_jobs import SPEC as BRANCH
from tests.unit.test_branch_jobs import _point as branch_point
from tests.unit.test_hysteresis_jobs import SPEC as HYSTERESIS
from tests.unit.test_hysteresis_jobs import _point as hysteresis_point

#: The tables whose ids the commands take and print, made AUTOINCREMENT by 0009.
ID_TABLES = ("sweeps", "runs", "continuations", "hysteresis_sweeps")
#: ... and those created so by later revisions (0016: curves).
LATER_ID_TABLES = ("curves",)


def _ids(db: Database, table: str, where: str = "") -> list[int]:
    with db.sessions() as s:
        return list(s.scalars(text(f"SELECT id FROM {table} {where} ORDER BY id")))


def _delete(db: Database, table: str, row_id: int) -> None:
    """What nothing in slopetui deletes (a continuation, a hysteresis sweep), as SQL would."""
    with db.transaction() as s:
        s.execute(text(f"DELETE FROM {table} WHERE id = :id"), {"id": row_id})


def _running_hysteresis_sweep(db: Database) -> int:
    """A hysteresis sweep running on w1 with three points saved, in plain SQL on the
    columns 0005 made: the models' statements name every column of the newest schema
    (0011 added some), which a store populated at an older revision does not have."""
    fields = {k: v for k, v in hysteresis_jobs.fields_of(HYSTERESIS).items() if k != "tol"}
    fields.update(status="running", worker_id="w1", attempts=1, n_done=3, runtime_s=0.3)
    names = ", ".join(f'"{n}"' for n in fields)  # quoted: window is a keyword on PostgreSQL
    with db.transaction() as s:
        sid = s.scalar(text(f"INSERT INTO hysteresis_sweeps ({names}, started_at, heartbeat_at) "
                            f"VALUES ({', '.join(':' + n for n in fields)}, CURRENT_TIMESTAMP, "
                            "CURRENT_TIMESTAMP) RETURNING id"), fields)
        for idx in range(3):
            # NaN as NULL, as the store's Measure columns write it (migration 0007)
            point = {k: None if isinstance(v, float) and math.isnan(v) else v
                     for k, v in hysteresis_point(idx).items()}
            s.execute(text(f"INSERT INTO hysteresis_points (sweep_id, {', '.join(point)}) "
                           f"VALUES (:sweep_id, {', '.join(':' + n for n in point)})"),
                      {"sweep_id": sid, **point})
    assert isinstance(sid, int)
    return sid


def populate(db: Database) -> dict[str, int]:
    """A row in every table but workers: a computed sweep, a queued one, a continuation
    with two points, a hysteresis sweep with three; returns the jobs' ids."""
    done = submit_quick(db, 3)
    finish_all(db)
    queued = submit_quick(db, 4)
    cid = branch_jobs.submit(db, BRANCH)
    continuations.claim(db, "w1")
    for idx in range(2):
        assert continuations.save_point(db, cid, "w1", branch_point(idx), 0.1)
    sid = _running_hysteresis_sweep(db)
    return {"done": done.sweep_id, "queued": queued.sweep_id, "continuation": cid,
            "hysteresis": sid}


def test_the_newest_sweeps_ids_are_not_handed_out_again(store):
    """SQLite took max(id) + 1: after the newest sweep was deleted the next submit was the
    same sweep id again, and its runs took the deleted runs' ids."""
    submit_quick(store, 3)
    doomed = submit_quick(store, 4).sweep_id
    doomed_runs = _ids(store, "runs", f"WHERE sweep_id = {doomed}")
    control.delete(store, doomed)
    again = submit_quick(store, 4).sweep_id
    assert again > doomed
    assert min(_ids(store, "runs", f"WHERE sweep_id = {again}")) > max(doomed_runs)


@pytest.mark.parametrize(("table", "submit"), [
    ("continuations", lambda db: branch_jobs.submit(db, BRANCH)),
    ("hysteresis_sweeps", lambda db: hysteresis_jobs.submit(db, HYSTERESIS))])
def test_the_newest_jobs_id_is_not_handed_out_again(store, table, submit):
    submit(store)
    doomed = submit(store)
    _delete(store, table, doomed)
    assert submit(store) > doomed


def _tables(db: Database) -> list[Any]:
    """The models' tables that the store's revision has (0014 added some after 0009)."""
    present = set(inspect(db.engine).get_table_names())
    return [t for t in Base.metadata.sorted_tables if t.name in present]


def _rows(db: Database) -> dict[str, list[tuple[Any, ...]]]:
    """Every row of every table, in key order."""
    out = {}
    with db.sessions() as s:
        for table in _tables(db):
            keys = ", ".join(c.name for c in table.primary_key.columns)
            out[table.name] = [tuple(r) for r in s.execute(
                text(f"SELECT * FROM {table.name} ORDER BY {keys}"))]
    return out


def _schema(db: Database) -> dict[str, Any]:
    """Each table's columns, indexes, foreign keys, CHECK constraints and primary key as
    the database reports them (the primary key's name apart: see _pk_names)."""
    found = inspect(db.engine)
    out: dict[str, Any] = {}
    for table in _tables(db):
        name = table.name
        out[name] = (
            [(c["name"], str(c["type"]), c["nullable"], c["default"])
             for c in found.get_columns(name)],
            sorted((i["name"], tuple(i["column_names"]), i["unique"])
                   for i in found.get_indexes(name)),
            sorted((f["name"], tuple(f["constrained_columns"]), f["referred_table"],
                    tuple(f["referred_columns"]), tuple(sorted(f["options"].items())))
                   for f in found.get_foreign_keys(name)),
            sorted((c["name"], c["sqltext"]) for c in found.get_check_constraints(name)),
            tuple(found.get_pk_constraint(name)["constrained_columns"]))
    return out


def _pk_names(db: Database) -> dict[str, str | None]:
    found = inspect(db.engine)
    return {t: found.get_pk_constraint(t)["name"] for t in ID_TABLES}


def _autoincrement(db: Database) -> set[str]:
    """The tables SQLite creates with AUTOINCREMENT."""
    with db.sessions() as s:
        return {name for name, sql in s.execute(text(
            "SELECT name, sql FROM sqlite_master WHERE type = 'table'"))
            if "AUTOINCREMENT" in sql}


def _sequence(db: Database) -> dict[str, int]:
    with db.sessions() as s:
        return {name: seq for name, seq in s.execute(text("SELECT name, seq FROM sqlite_sequence"))}


def test_the_models_name_the_same_tables_as_the_migration():
    import importlib
    migration = importlib.import_module("migrations.versions.0009_ids_never_reused")
    marked = {t.name for t in Base.metadata.sorted_tables
              if t.dialect_options["sqlite"]["autoincrement"]}
    assert marked == set(migration.TABLES) | set(LATER_ID_TABLES)
    assert set(migration.TABLES) == set(ID_TABLES)


def test_0009_keeps_every_row_and_then_no_id_comes_back(new_store_url, backend):
    """A store at 0008 with rows in every table and gaps in its ids (a deleted sweep, a
    deleted continuation): 0009 keeps every row and the schema, ids go on above the
    largest, and the downgrade gives back 0008's schema with every row."""
    db = Database(new_store_url)
    upgrade(db)  # the models' statements name the newest columns: the rows are written
    first = populate(db)  # at the head, then taken back to 0008
    populate(db)
    control.delete(db, first["queued"])  # a gap in sweeps and in runs
    _delete(db, "continuations", first["continuation"])
    downgrade(db, "0008")
    rows, schema, pk_names = _rows(db), _schema(db), _pk_names(db)
    if backend == "sqlite":
        assert _autoincrement(db) == set()
        assert set(pk_names.values()) == {f"pk_{t}" for t in ID_TABLES}

    command.upgrade(alembic_config(db), "0009")
    assert current_revision(db) == "0009"
    assert _rows(db) == rows
    assert _schema(db) == schema
    assert integrity_problems(db) == []
    if backend == "sqlite":
        assert _autoincrement(db) == set(ID_TABLES)
        assert _sequence(db) == {t: max(_ids(db, t)) for t in ID_TABLES}
    else:
        assert _pk_names(db) == pk_names

    newest = {t: max(_ids(db, t)) for t in ID_TABLES}
    upgrade(db)  # to the head, where the models' statements run
    last = populate(db)
    assert last["done"] > newest["sweeps"]
    control.delete(db, last["queued"])  # the newest of each, deleted
    _delete(db, "continuations", last["continuation"])
    _delete(db, "hysteresis_sweeps", last["hysteresis"])
    gone_run = max(_ids(db, "runs"))
    again = populate(db)
    assert again["done"] > last["queued"]
    assert min(_ids(db, "runs", f"WHERE sweep_id = {again['done']}")) > gone_run + 4
    assert again["continuation"] > last["continuation"]
    assert again["hysteresis"] > last["hysteresis"]

    downgrade(db, "0009")
    rows = _rows(db)
    downgrade(db, "0008")
    assert _rows(db) == rows
    assert _schema(db) == schema
    assert _pk_names(db) == pk_names
    if backend == "sqlite":
        assert _autoincrement(db) == set()
    db.dispose()


def test_later_migrations_keep_autoincrement_and_the_largest_id_ever_handed_out(
        new_store_url, backend):
    """A migration after 0009 that rebuilds a table on SQLite (0010 widens two columns of
    runs) rebuilds it from its reflection, which knows no AUTOINCREMENT: 0010 dropped it
    from runs, and the copy seeded sqlite_sequence with the largest id left, below the
    newest runs deleted before. Found when 0010 was merged after 0009."""
    db = Database(new_store_url)
    upgrade(db)  # written at the head (the models' statements name its columns), then
    populate(db)  # taken back to 0009
    last = populate(db)
    control.delete(db, last["queued"])  # the newest runs, deleted
    downgrade(db, "0009")
    gone_run = max(_ids(db, "runs")) + 4
    upgrade(db)  # to the head
    if backend == "sqlite":
        assert _autoincrement(db) == set(ID_TABLES) | set(LATER_ID_TABLES)
        assert _sequence(db)["runs"] >= gone_run
    again = populate(db)
    assert min(_ids(db, "runs", f"WHERE sweep_id = {again['done']}")) > gone_run
    downgrade(db, "0009")
    if backend == "sqlite":
        assert _autoincrement(db) == set(ID_TABLES)
        assert _sequence(db)["runs"] >= gone_run + 7
    db.dispose()
