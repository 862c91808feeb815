"""Hysteresis transitions as brackets, then refined: the grid's bracket of each branch's
transition and the tolerance it was refined to.

Revision ID: 0011
Revises: 0010
Create Date: 2026-12-03 11:20:00

``onset_up`` and ``offset_down`` were the first grid value past each transition; they are
now refined by bisection inside the grid's bracket (core.hysteresis.refine), and the
bracket is kept beside them: ``onset_up_before``/``onset_up_after`` (the last value of the
up branch on its old attractor, the first on the new) and ``offset_down_before``/
``offset_down_after``, with ``tol``, the relative tolerance a sweep asks for. Sweeps
stored before this revision keep their grid values, read NULL brackets (nothing was
refined), and ``tol`` 1e-3, the default, for a sweep resumed after the upgrade.

Plain ADD COLUMN, which SQLite does in place: hysteresis_sweeps keeps 0009's
AUTOINCREMENT and sqlite_sequence (no rebuild). The downgrade drops the columns, in place
too (SQLite >= 3.35): the brackets and tolerances go, the refined values stay in onset_up
and offset_down.
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision: str = "0011"
down_revision: str | None = "0010"
branch_labels = None
depends_on = None

#: The bracket columns, each nullable (no transition, or a sweep stored before 0011).
BRACKETS = ("onset_up_before", "onset_up_after", "offset_down_before", "offset_down_after")


def upgrade() -> None:
    op.add_column("hysteresis_sweeps",
                  sa.Column("tol", sa.Double(), nullable=False, server_default="0.001"))
    for name in BRACKETS:
        op.add_column("hysteresis_sweeps", sa.Column(name, sa.Double(), nullable=True))


def downgrade() -> None:
    for name in (*BRACKETS[::-1], "tol"):
        op.drop_column("hysteresis_sweeps", name)
