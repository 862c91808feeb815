"""What a tracker keeps: a note on each sweep, tags on sweeps, and the runs marked for
comparison, which used to live in the application's memory and went with it.

Revision ID: 0014
Revises: 0013
Create Date: 2026-12-03 19:15:00

New column of ``sweeps``: ``note`` (text, NULL for none). Plain ADD COLUMN, in place on
SQLite (sweeps keeps 0009's AUTOINCREMENT); the downgrade drops it in place too (SQLite
>= 3.35).

New tables:
- ``sweep_tags`` (sweep_id, tag): a sweep's tags, one row each, gone with the sweep
  (ON DELETE CASCADE, and ``store.sweeps.writes.delete_sweep`` deletes them itself, as it
  clears every other reference: SQLite's foreign_keys pragma is per connection); indexed
  by tag, which ``runs --tag`` looks up first;
- ``marks`` (id, run_id unique): the runs marked for comparison, in the order marked
  (``id``), gone with their run likewise.
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision: str = "0014"
down_revision: str | None = "0013"
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.add_column("sweeps", sa.Column("note", sa.Text(), nullable=True))
    op.create_table(
        "sweep_tags",
        sa.Column("sweep_id", sa.Integer(), nullable=False),
        sa.Column("tag", sa.String(length=32), nullable=False),
        sa.ForeignKeyConstraint(["sweep_id"], ["sweeps.id"],
                                name=op.f("fk_sweep_tags_sweep_id_sweeps"), ondelete="CASCADE"),
        sa.PrimaryKeyConstraint("sweep_id", "tag", name=op.f("pk_sweep_tags")),
    )
    op.create_index("ix_sweep_tags_tag", "sweep_tags", ["tag"])
    op.create_table(
        "marks",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("run_id", sa.Integer(), nullable=False),
        sa.ForeignKeyConstraint(["run_id"], ["runs.id"], name=op.f("fk_marks_run_id_runs"),
                                ondelete="CASCADE"),
        sa.PrimaryKeyConstraint("id", name=op.f("pk_marks")),
        sa.UniqueConstraint("run_id", name=op.f("uq_marks_run_id")),
    )


def downgrade() -> None:
    op.drop_table("marks")
    op.drop_index("ix_sweep_tags_tag", table_name="sweep_tags")
    op.drop_table("sweep_tags")
    op.drop_column("sweeps", "note")
