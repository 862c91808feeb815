"""Histories and initial conditions: the history each run starts from, which of its
sweep's initial conditions it is, and the final states histories name.

Revision ID: 0006
Revises: 0005
Create Date: 2026-12-01 21:46:22.112839

The new columns of runs carry literal server defaults ('constant', '0'): every run
stored before started from the constant history, its sweep's only initial condition;
and a literal keeps SQLite's batch mode at ALTER TABLE ADD COLUMN (see 0002).
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision: str = "0006"
down_revision: str | None = "0005"
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.create_table(
        "initial_states",
        sa.Column("name", sa.String(length=24), nullable=False),
        sa.Column("source_run", sa.Integer(), nullable=True),
        sa.Column("tau", sa.Double(), nullable=False),
        sa.Column("dt", sa.Double(), nullable=False),
        sa.Column("state", sa.LargeBinary(), nullable=False),
        sa.Column(
            "created_at",
            sa.DateTime(),
            server_default=sa.text("(CURRENT_TIMESTAMP)"),
            nullable=False,
        ),
        sa.ForeignKeyConstraint(
            ["source_run"],
            ["runs.id"],
            name=op.f("fk_initial_states_source_run_runs"),
            ondelete="SET NULL",
        ),
        sa.PrimaryKeyConstraint("name", name=op.f("pk_initial_states")),
    )
    with op.batch_alter_table("runs", schema=None) as batch_op:
        batch_op.add_column(
            sa.Column("history", sa.String(length=24), server_default="constant", nullable=False)
        )
        batch_op.add_column(sa.Column("ic", sa.Integer(), server_default="0", nullable=False))


def downgrade() -> None:
    with op.batch_alter_table("runs", schema=None) as batch_op:
        batch_op.drop_column("ic")
        batch_op.drop_column("history")

    op.drop_table("initial_states")
