"""Migration 0015: a queued continuation keeps the index of its Hopf point. Every "hopf"
continuation stored before it started at the first (the command refused the others); the
downgrade names the later ones it can no longer tell apart, and fails those not yet
computed, which an older worker would start at the first Hopf point."""

from __future__ import annotations

from alembic import command
from sqlalchemy import inspect

from core.branch_start import BranchSpec
from core.params import Params
from slopetui.queue import branch_jobs
from slopetui.store.database import Database
from slopetui.store.migrate import alembic_config, downgrade, plan_downgrade, upgrade

HOPF = BranchSpec(Params(tau=10.0), "k", 0.01, from_hopf=True, max_points=4)
ORBIT = BranchSpec(Params(tau=10.0, k=8.0), "k", 0.01, from_hopf=False, max_points=4)


def _columns(db: Database) -> set[str]:
    return {c["name"] for c in inspect(db.engine).get_columns("continuations")}


def _rows(db: Database) -> dict[int, tuple[str, str, str | None]]:
    with db.engine.begin() as conn:
        return {int(r[0]): (r[1], r[2], r[3]) for r in conn.exec_driver_sql(
            "SELECT id, start, status, error FROM continuations ORDER BY id")}


def _hopf_branch(db: Database, cid: int) -> int | None:
    """The stored index, in plain SQL: at revision 0015 the models' statements would name
    the columns later revisions add (0016's l1)."""
    with db.engine.connect() as conn:
        return conn.exec_driver_sql(
            f"SELECT hopf_branch FROM continuations WHERE id = {cid}").scalar()


def test_0015_names_the_first_hopf_point_of_older_rows_and_its_downgrade_what_goes(
        new_store_url, backend):
    db = Database(new_store_url)
    upgrade(db)  # written at the head (the models' statements), then taken back to 0014
    hopf, orbit = branch_jobs.submit(db, HOPF), branch_jobs.submit(db, ORBIT)
    downgrade(db, "0014")
    assert "hopf_branch" not in _columns(db)
    command.upgrade(alembic_config(db), "0015")
    assert _hopf_branch(db, hopf) == 1
    assert _hopf_branch(db, orbit) is None
    assert plan_downgrade(db, "0014").dropped == "no stored data"

    second = branch_jobs.submit(db, BranchSpec(**{**vars(HOPF), "hopf_branch": 2}))
    third = branch_jobs.submit(db, BranchSpec(**{**vars(HOPF), "hopf_branch": 3}))
    with db.engine.begin() as conn:  # computed: its points stay, under the first's name
        conn.exec_driver_sql(f"UPDATE continuations SET status = 'done' WHERE id = {third}")
    assert _hopf_branch(db, second) == 2
    assert plan_downgrade(db, "0014").dropped == \
        "the Hopf point (a later one than the first) of 2 continuations"
    command.downgrade(alembic_config(db), "0014")
    assert "hopf_branch" not in _columns(db)
    rows = _rows(db)
    assert rows[hopf][1:] == rows[orbit][1:] == ("queued", None)
    assert rows[third][1:] == ("done", None)
    status, error = rows[second][1:]
    assert status == "failed" and "below revision 0015" in str(error)
    db.dispose()
