"""Hysteresis sweeps as jobs: their points, each with the state it hands over.

Revision ID: 0005
Revises: 0004
Create Date: 2026-12-01 21:34:24.567039

Only new tables: the runs, sweeps and continuations stored before are untouched.
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision: str = "0005"
down_revision: str | None = "0004"
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.create_table(
        "hysteresis_sweeps",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("param", sa.String(length=8), nullable=False),
        sa.Column("start", sa.Double(), nullable=False),
        sa.Column("stop", sa.Double(), nullable=False),
        sa.Column("n_points", sa.Integer(), nullable=False),
        sa.Column("a", sa.Double(), nullable=False),
        sa.Column("b", sa.Double(), nullable=False),
        sa.Column("c", sa.Double(), nullable=False),
        sa.Column("d", sa.Double(), nullable=False),
        sa.Column("k", sa.Double(), nullable=False),
        sa.Column("v", sa.Double(), nullable=False),
        sa.Column("tau", sa.Double(), nullable=False),
        sa.Column("delta", sa.Double(), nullable=False),
        sa.Column("dt", sa.Double(), nullable=False),
        sa.Column("t_settle", sa.Double(), nullable=False),
        sa.Column("window", sa.Double(), nullable=False),
        sa.Column("engine", sa.String(length=16), nullable=False),
        sa.Column("status", sa.String(length=16), nullable=False),
        sa.Column("worker_id", sa.String(length=128), nullable=True),
        sa.Column("attempts", sa.Integer(), nullable=False),
        sa.Column(
            "created_at",
            sa.DateTime(),
            server_default=sa.text("(CURRENT_TIMESTAMP)"),
            nullable=False,
        ),
        sa.Column("started_at", sa.DateTime(), nullable=True),
        sa.Column("heartbeat_at", sa.DateTime(), nullable=True),
        sa.Column("finished_at", sa.DateTime(), nullable=True),
        sa.Column("error", sa.Text(), nullable=True),
        sa.Column("onset_up", sa.Double(), nullable=True),
        sa.Column("offset_down", sa.Double(), nullable=True),
        sa.Column("n_done", sa.Integer(), server_default="0", nullable=False),
        sa.Column("runtime_s", sa.Double(), server_default="0", nullable=False),
        sa.CheckConstraint(
            "status IN ('queued', 'running', 'done', 'failed', 'cancelled')",
            name=op.f("ck_hysteresis_sweeps_status"),
        ),
        sa.PrimaryKeyConstraint("id", name=op.f("pk_hysteresis_sweeps")),
    )
    with op.batch_alter_table("hysteresis_sweeps", schema=None) as batch_op:
        batch_op.create_index(
            batch_op.f("ix_hysteresis_sweeps_status_id"), ["status", "id"], unique=False
        )

    op.create_table(
        "hysteresis_points",
        sa.Column("sweep_id", sa.Integer(), nullable=False),
        sa.Column("idx", sa.Integer(), nullable=False),
        sa.Column("direction", sa.String(length=4), nullable=False),
        sa.Column("value", sa.Double(), nullable=False),
        sa.Column("regime", sa.String(length=16), nullable=False),
        sa.Column("detail", sa.Text(), nullable=False),
        sa.Column("amplitude", sa.Double(), nullable=True),
        sa.Column("growth", sa.Double(), nullable=True),
        sa.Column("jumped", sa.Boolean(), nullable=False),
        sa.Column("state", sa.LargeBinary(), nullable=True),
        sa.CheckConstraint(
            "direction IN ('up', 'down')", name=op.f("ck_hysteresis_points_direction")
        ),
        sa.ForeignKeyConstraint(
            ["sweep_id"],
            ["hysteresis_sweeps.id"],
            name=op.f("fk_hysteresis_points_sweep_id_hysteresis_sweeps"),
            ondelete="CASCADE",
        ),
        sa.PrimaryKeyConstraint("sweep_id", "idx", name=op.f("pk_hysteresis_points")),
    )


def downgrade() -> None:
    op.drop_table("hysteresis_points")
    with op.batch_alter_table("hysteresis_sweeps", schema=None) as batch_op:
        batch_op.drop_index(batch_op.f("ix_hysteresis_sweeps_status_id"))

    op.drop_table("hysteresis_sweeps")
