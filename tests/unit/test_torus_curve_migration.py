"""Migration 0017: ``curves.kind`` may be 'ns' (torus curves). On SQLite the table is
rebuilt for its CHECK: every curve and point stays, and an id handed out before (even of a
curve deleted since) is not handed out again. The downgrade names and drops the torus
curves with their points, and puts the older CHECK back."""

from __future__ import annotations

import pytest
from alembic import command
from sqlalchemy import exc, text

from core.curve_start import CurveSpec
from core.params import Params
from slopetui.queue import curve_jobs
from slopetui.store.database import Database
from slopetui.store.migrate import alembic_config, plan_downgrade, upgrade

FOLD = CurveSpec(Params(tau=2.0), "k", "tau", "fold", 0.01, 1.5, 6, 0.2)
TORUS = CurveSpec(Params(tau=10.0), "k", "tau", "ns", 0.01, 10.4, 5, 0.25, hopf_branch=2,
                  branch_end=25.0)


def _sql(db: Database, statement: str) -> list[tuple]:
    with db.engine.begin() as conn:
        result = conn.exec_driver_sql(statement)
        return [tuple(r) for r in result] if result.returns_rows else []


def _point(db: Database, cid: int) -> None:
    _sql(db, "INSERT INTO curve_points (curve_id, idx, first, second, period) "
             f"VALUES ({cid}, 0, 5.2, 10.0, 5.3)")


def _copy_of(db: Database, cid: int, kind: str) -> int:
    """A copy of curve ``cid`` with another kind, in plain SQL (at 0016 the models would
    write the kind through the newer CHECK's eyes)."""
    cols = ", ".join([*(c for c in curve_jobs.fields_of(FOLD) if c != "kind"), "attempts"])
    (new,), = _sql(db, f"INSERT INTO curves (kind, {cols}) SELECT '{kind}', {cols} "
                       f"FROM curves WHERE id = {cid} RETURNING id")
    return int(new)


def test_0017_takes_torus_curves_keeps_the_rest_and_its_downgrade_drops_them(
        new_store_url, backend):
    db = Database(new_store_url)
    upgrade(db)
    fold = curve_jobs.submit(db, FOLD)
    _point(db, fold)
    gone = curve_jobs.submit(db, FOLD)
    _sql(db, f"DELETE FROM curves WHERE id = {gone}")  # the newest id, deleted
    torus = curve_jobs.submit(db, TORUS)
    _point(db, torus)
    assert plan_downgrade(db, "0016").dropped == "1 torus curve (1 point)"
    command.downgrade(alembic_config(db), "0016")
    assert _sql(db, "SELECT id, kind FROM curves ORDER BY id") == [(fold, "fold")]
    assert _sql(db, "SELECT curve_id FROM curve_points") == [(fold,)]
    with pytest.raises(exc.IntegrityError):  # the older CHECK is back
        _copy_of(db, fold, "ns")
    command.upgrade(alembic_config(db), "0017")
    assert _sql(db, "SELECT id, kind FROM curves ORDER BY id") == [(fold, "fold")]
    assert _sql(db, "SELECT curve_id, idx FROM curve_points") == [(fold, 0)]
    again = _copy_of(db, fold, "ns")
    assert again > torus > gone  # no id handed out before comes back
    with pytest.raises(exc.IntegrityError):
        _copy_of(db, fold, "torus")
    with db.engine.connect() as conn:  # the queue's index and status CHECK survive
        if backend == "sqlite":
            sql = conn.execute(text("SELECT sql FROM sqlite_master WHERE name = 'curves'")).scalar()
            assert "ck_curves_status" in sql and "AUTOINCREMENT" in sql
            assert conn.execute(text("SELECT count(*) FROM sqlite_master "
                                     "WHERE name = 'ix_curves_status_id'")).scalar() == 1
    with pytest.raises(exc.IntegrityError):
        _sql(db, f"UPDATE curves SET status = 'lost' WHERE id = {fold}")
    db.dispose()
