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


def toggle_mark(db: Database, run_id: int) -> tuple[bool, tuple[int, ...]] | None:
    """Mark the run, or unmark it if it is marked: (whether it is marked now, every
    marked run in order); None if there is no such run."""
    with db.transaction() as s:
        if s.get(Run, run_id) is None:
            return None
        removed = rows_changed(s.execute(delete(Mark).where(Mark.run_id == run_id)))
        if not removed:
            s.execute(insert(Mark).values(run_id=run_id))
        return not removed, tuple(s.scalars(select(Mark.run_id).order_by(Mark.id)))


def clear_marks(db: Database) -> int:
    """Unmark every run; how many were marked."""
    with db.transaction() as s:
        return rows_changed(s.execute(delete(Mark)))
