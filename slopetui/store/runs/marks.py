"""The runs marked for comparison (m in the application; v compares them), kept in the
store so that they survive a restart of the application. One list per store, in the
order marked; a mark goes with its run (a deleted sweep takes its runs' marks)."""

from __future__ import annotations

from typing import Any

from sqlalchemy import delete, select
from sqlalchemy.dialects import postgresql, sqlite

from slopetui.store.database import Database, rows_changed
from slopetui.store.models import Mark, Run


def marked_runs(db: Database) -> tuple[int, ...]:
    """The marked runs' ids, in the order marked."""
    with db.read() as conn:
        return tuple(conn.scalars(select(Mark.run_id).order_by(Mark.id)))


def set_mark(db: Database, run_id: int, marked: bool) -> tuple[int, ...]:
    """Mark the run (after the others) or unmark it; as it is already: nothing changes, and
    a run the store does not hold (deleted meanwhile) is not marked. Every marked run, in
    order. Idempotent, so that the application's writes, done off its UI thread in any
    order, leave what it shows."""
    with db.transaction() as s:
        if not marked:
            s.execute(delete(Mark).where(Mark.run_id == run_id))
        elif (s.get(Run, run_id) is not None
              and s.scalar(select(Mark.id).where(Mark.run_id == run_id)) is None):
            # on PostgreSQL another application may mark the run between the read and the
            # insert (two transactions at once): its mark stands, as this one would
            s.execute(_insert_new_mark(s.get_bind().dialect.name).values(run_id=run_id)
                      .on_conflict_do_nothing(index_elements=[Mark.run_id]))
        return tuple(s.scalars(select(Mark.run_id).order_by(Mark.id)))


def _insert_new_mark(dialect: str) -> Any:
    """The dialect's INSERT, which has ON CONFLICT DO NOTHING (both backends' do)."""
    if dialect == "postgresql":
        return postgresql.insert(Mark)
    return sqlite.insert(Mark)


def clear_marks(db: Database) -> int:
    """Unmark every run; how many were marked."""
    with db.transaction() as s:
        return rows_changed(s.execute(delete(Mark)))
