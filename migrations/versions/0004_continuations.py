"""Continuations of periodic orbits as jobs: their branch points and bifurcations.

Revision ID: 0004
Revises: 0003
Create Date: 2026-12-01 20:55:57.847020

Only new tables: the runs and sweeps stored before are untouched.
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision: str = "0004"
down_revision: str | None = "0003"
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.create_table(
        "continuations",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("param", sa.String(length=8), nullable=False),
        sa.Column("start", sa.String(length=8), nullable=False),
        sa.Column("a", sa.Double(), nullable=False),
        sa.Column("b", sa.Double(), nullable=False),
        sa.Column("c", sa.Double(), nullable=False),
        sa.Column("d", sa.Double(), nullable=False),
        sa.Column("k", sa.Double(), nullable=False),
        sa.Column("v", sa.Double(), nullable=False),
        sa.Column("tau", sa.Double(), nullable=False),
        sa.Column("delta", sa.Double(), nullable=False),
        sa.Column("from_run", sa.Integer(), nullable=True),
        sa.Column("dt", sa.Double(), nullable=False),
        sa.Column("end_value", sa.Double(), nullable=True),
        sa.Column("max_points", sa.Integer(), nullable=False),
        sa.Column("max_step", sa.Double(), nullable=False),
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
        sa.Column("hopf_value", sa.Double(), nullable=True),
        sa.Column("hopf_period", sa.Double(), nullable=True),
        sa.Column("criticality", sa.String(length=16), nullable=True),
        sa.Column("end_reason", sa.Text(), nullable=True),
        sa.Column("n_points", sa.Integer(), server_default="0", nullable=False),
        sa.Column("runtime_s", sa.Double(), server_default="0", nullable=False),
        sa.CheckConstraint("start IN ('hopf', 'orbit')", name=op.f("ck_continuations_start")),
        sa.CheckConstraint(
            "status IN ('queued', 'running', 'done', 'failed', 'cancelled')",
            name=op.f("ck_continuations_status"),
        ),
        sa.ForeignKeyConstraint(
            ["from_run"],
            ["runs.id"],
            name=op.f("fk_continuations_from_run_runs"),
            ondelete="SET NULL",
        ),
        sa.PrimaryKeyConstraint("id", name=op.f("pk_continuations")),
    )
    with op.batch_alter_table("continuations", schema=None) as batch_op:
        batch_op.create_index(
            batch_op.f("ix_continuations_status_id"), ["status", "id"], unique=False
        )

    op.create_table(
        "bifurcations",
        sa.Column("continuation_id", sa.Integer(), nullable=False),
        sa.Column("idx", sa.Integer(), nullable=False),
        sa.Column("type", sa.String(length=16), nullable=False),
        sa.Column("value", sa.Double(), nullable=False),
        sa.Column("period", sa.Double(), nullable=False),
        sa.Column("mu_re", sa.Double(), nullable=False),
        sa.Column("mu_im", sa.Double(), nullable=False),
        sa.ForeignKeyConstraint(
            ["continuation_id"],
            ["continuations.id"],
            name=op.f("fk_bifurcations_continuation_id_continuations"),
            ondelete="CASCADE",
        ),
        sa.PrimaryKeyConstraint("continuation_id", "idx", name=op.f("pk_bifurcations")),
    )
    op.create_table(
        "branch_points",
        sa.Column("continuation_id", sa.Integer(), nullable=False),
        sa.Column("idx", sa.Integer(), nullable=False),
        sa.Column("value", sa.Double(), nullable=False),
        sa.Column("period", sa.Double(), nullable=False),
        sa.Column("amplitude", sa.Double(), nullable=False),
        sa.Column("stable", sa.Boolean(), nullable=False),
        sa.Column("unstable_count", sa.Integer(), nullable=False),
        sa.Column("leading_re", sa.Double(), nullable=False),
        sa.Column("leading_im", sa.Double(), nullable=False),
        sa.Column("multipliers", sa.JSON(), nullable=False),
        sa.Column("flow_index", sa.Integer(), nullable=False),
        sa.Column("translation", sa.Double(), nullable=False),
        sa.Column("step", sa.Double(), nullable=False),
        sa.Column("state", sa.LargeBinary(), nullable=False),
        sa.ForeignKeyConstraint(
            ["continuation_id"],
            ["continuations.id"],
            name=op.f("fk_branch_points_continuation_id_continuations"),
            ondelete="CASCADE",
        ),
        sa.PrimaryKeyConstraint("continuation_id", "idx", name=op.f("pk_branch_points")),
    )


def downgrade() -> None:
    op.drop_table("branch_points")
    op.drop_table("bifurcations")
    with op.batch_alter_table("continuations", schema=None) as batch_op:
        batch_op.drop_index(batch_op.f("ix_continuations_status_id"))

    op.drop_table("continuations")
