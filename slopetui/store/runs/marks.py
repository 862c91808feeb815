"""The runs marked for comparison (m in the application; v compares them), kept in the
store so that they survive a restart of the application. One list per store, in the
order marked; a mark goes with its run (a deleted sweep takes its runs' marks)."""

from __future__ import annotations

from sqlalchemy import delete, insert, select

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
            s.execute(insert(Mark).values(run_id=run_id))
        return tuple(s.scalars(select(Mark.run_id).order_by(Mark.id)))


def clear_marks(db: Database) -> int:
    """Unmark every run; how many were marked."""
    with db.transaction() as s:
        return rows_changed(s.execute(delete(Mark)))
