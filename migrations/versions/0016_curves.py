"""Curves in two parameters as jobs: the fold of cycles, the Hopf curve and the period
doubling, their points and their codimension-two points.

Revision ID: 0016
Revises: 0015
Create Date: 2026-12-03 23:30:00

Only new tables (the runs, sweeps, continuations and hysteresis sweeps stored before are
untouched):
- ``curves``: what was asked (kind fold, hopf or pd, the two parameters, the starting
  point, dt, where param2 ends, the point budget, the largest step, the Hopf point it
  starts from, where a pd curve's branch is followed to, the engine), the queue's
  columns as every job's, and why it ended; ids never reused (AUTOINCREMENT on SQLite, as
  0009 made the other job tables);
- ``curve_points``: each point as computed, with what a resumption needs;
- ``curve_bifurcations``: the codimension-two points of a finished curve.

New column of ``bifurcations``: ``reason`` (text, NULL for none): what decided a
multiplier's crossing on a continuation's branch (real against its uncertainty, or
undetermined). New column of ``continuations``: ``l1`` (real, NULL for an orbit start and
for the branches stored before): the first Lyapunov coefficient at the Hopf point, whose
sign the criticality now is. Plain ADD COLUMNs, in place on SQLite.

The downgrade drops the three tables (their curves are lost) and the columns (the reasons
and the l1 values are lost; the bifurcations and continuations stay): downgrade_losses
names them.
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision: str = "0016"
down_revision: str | None = "0015"
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.add_column("bifurcations", sa.Column("reason", sa.Text(), nullable=True))
    op.add_column("continuations", sa.Column("l1", sa.Double(), nullable=True))
    op.create_table(
        "curves",
        sa.Column("id", sa.Integer(), nullable=False),
        sa.Column("kind", sa.String(length=8), nullable=False),
        sa.Column("param", sa.String(length=8), nullable=False),
        sa.Column("param2", sa.String(length=8), nullable=False),
        *(sa.Column(name, sa.Double(), nullable=False)
          for name in ("a", "b", "c", "d", "k", "v", "tau", "delta")),
        sa.Column("dt", sa.Double(), nullable=False),
        sa.Column("end_value", sa.Double(), nullable=False),
        sa.Column("max_points", sa.Integer(), nullable=False),
        sa.Column("max_step", sa.Double(), nullable=False),
        sa.Column("hopf_branch", sa.Integer(), server_default="1", nullable=False),
        sa.Column("branch_end", sa.Double(), nullable=True),
        sa.Column("engine", sa.String(length=16), nullable=False),
        sa.Column("end_reason", sa.Text(), nullable=True),
        sa.Column("n_points", sa.Integer(), server_default="0", nullable=False),
        sa.Column("runtime_s", sa.Double(), server_default="0", nullable=False),
        sa.Column("status", sa.String(length=16), nullable=False),
        sa.Column("worker_id", sa.String(length=128), nullable=True),
        sa.Column("attempts", sa.Integer(), nullable=False),
        sa.Column("created_at", sa.DateTime(), server_default=sa.text("(CURRENT_TIMESTAMP)"),
                  nullable=False),
        sa.Column("started_at", sa.DateTime(), nullable=True),
        sa.Column("heartbeat_at", sa.DateTime(), nullable=True),
        sa.Column("finished_at", sa.DateTime(), nullable=True),
        sa.Column("error", sa.Text(), nullable=True),
        sa.CheckConstraint("kind IN ('fold', 'hopf', 'pd')", name=op.f("ck_curves_kind")),
        sa.CheckConstraint("status IN ('queued', 'running', 'done', 'failed', 'cancelled')",
                           name=op.f("ck_curves_status")),
        sa.PrimaryKeyConstraint("id", name=op.f("pk_curves")),
        sqlite_autoincrement=True,
    )
    op.create_index(op.f("ix_curves_status_id"), "curves", ["status", "id"], unique=False)
    op.create_table(
        "curve_points",
        sa.Column("curve_id", sa.Integer(), nullable=False),
        sa.Column("idx", sa.Integer(), nullable=False),
        sa.Column("first", sa.Double(), nullable=False),
        sa.Column("second", sa.Double(), nullable=False),
        sa.Column("period", sa.Double(), nullable=False),
        sa.Column("amplitude", sa.Double(), nullable=True),
        sa.Column("l1", sa.Double(), nullable=True),
        sa.Column("curvature", sa.Double(), nullable=True),
        sa.Column("multipliers", sa.JSON(), nullable=True),
        sa.Column("flow_index", sa.Integer(), nullable=True),
        sa.Column("translation", sa.Double(), nullable=True),
        sa.Column("newton_steps", sa.Integer(), nullable=True),
        sa.Column("step", sa.Double(), nullable=True),
        sa.Column("state", sa.LargeBinary(), nullable=True),
        sa.ForeignKeyConstraint(["curve_id"], ["curves.id"],
                                name=op.f("fk_curve_points_curve_id_curves"),
                                ondelete="CASCADE"),
        sa.PrimaryKeyConstraint("curve_id", "idx", name=op.f("pk_curve_points")),
    )
    op.create_table(
        "curve_bifurcations",
        sa.Column("curve_id", sa.Integer(), nullable=False),
        sa.Column("idx", sa.Integer(), nullable=False),
        sa.Column("type", sa.String(length=16), nullable=False),
        sa.Column("first", sa.Double(), nullable=False),
        sa.Column("second", sa.Double(), nullable=False),
        sa.Column("period", sa.Double(), nullable=False),
        sa.Column("note", sa.Text(), nullable=False),
        sa.ForeignKeyConstraint(["curve_id"], ["curves.id"],
                                name=op.f("fk_curve_bifurcations_curve_id_curves"),
                                ondelete="CASCADE"),
        sa.PrimaryKeyConstraint("curve_id", "idx", name=op.f("pk_curve_bifurcations")),
    )


def downgrade() -> None:
    op.drop_table("curve_bifurcations")
    op.drop_table("curve_points")
    op.drop_index(op.f("ix_curves_status_id"), table_name="curves")
    op.drop_table("curves")
    op.drop_column("bifurcations", "reason")
    op.drop_column("continuations", "l1")
