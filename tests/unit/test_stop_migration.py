"""Migration 0013: every run stored before it ran to its t_end (the paper's protocol), and
its t_stop is what it kept: t_end, or t_blowup where the explicit scheme blew up and
nothing took over; the downgrade names the stop rules it drops."""

from __future__ import annotations

from alembic import command
from sqlalchemy import inspect

from slopetui.store.database import Database
from slopetui.store.migrate import alembic_config, downgrade, plan_downgrade, upgrade
from tests.support import finish_all, submit_quick


def _set(db: Database, run_id: int, sql: str) -> None:
    with db.engine.begin() as conn:
        conn.exec_driver_sql(f"UPDATE runs SET {sql} WHERE id = {run_id}")


def _stops(db: Database) -> dict[int, tuple[str, float | None]]:
    with db.engine.begin() as conn:
        return {int(r[0]): (r[1], r[2]) for r in
                conn.exec_driver_sql("SELECT id, stop, t_stop FROM runs ORDER BY id")}


def test_0013_backfills_t_stop_and_names_the_rule_every_older_run_ran_under(
        new_store_url, backend):
    db = Database(new_store_url)
    upgrade(db)  # the rows are written at the head (the models' statements), then taken
    done = submit_quick(db, 4)  # back to 0012, where they are what 0012 kept
    finish_all(db)
    submit_quick(db, 1, tau=3.0)  # queued: nothing to backfill
    downgrade(db, "0012")
    assert "stop" not in {c["name"] for c in inspect(db.engine).get_columns("runs")}
    with db.engine.begin() as conn:
        first, second, third, fourth = (r[0] for r in conn.exec_driver_sql(
            f"SELECT id FROM runs WHERE sweep_id = {done.sweep_id} ORDER BY id"))
    _set(db, first, "t_blowup = 37.5")  # blew up, nothing took over
    _set(db, second, "t_blowup = 12.0, flags = 'stiff-fallback'")  # the stiff run went on
    _set(db, third, "t_blowup = 3.0, flags = 'stiff-fallback', attractor = 'divergent'")

    command.upgrade(alembic_config(db), "0013")
    stops = _stops(db)
    t_end = 200.0  # tests.support.QUICK_SOLVER's
    assert stops[first] == ("t_end", 37.5)
    assert stops[second] == ("t_end", t_end)
    assert stops[third] == ("t_end", None)  # the stiff scheme's own blow-up was not kept
    assert stops[fourth] == ("t_end", t_end)
    queued = max(stops)
    assert stops[queued] == ("t_end", None)

    assert plan_downgrade(db, "0012").dropped == "no stored data"
    _set(db, fourth, "stop = 'certified', t_stop = 150.0")
    assert plan_downgrade(db, "0012").dropped == \
        "the stop rule (certified) and stopping time of 1 run"
    command.downgrade(alembic_config(db), "0012")
    columns = {c["name"] for c in inspect(db.engine).get_columns("runs")}
    assert not {"stop", "t_stop"} & columns and "certified" in columns
    db.dispose()
