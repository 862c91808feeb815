"""Labels that follow linear theory: room for the attractor unstable-fixed-point and for
the reason of an undetermined regime.

Revision ID: 0010
Revises: 0009
Create Date: 2026-12-03 10:30:00

A window that still sits at a rest state linear theory calls unstable is attractor
``unstable-fixed-point`` (20 characters; the column held 16, which PostgreSQL enforces)
and its detail says where the run is headed or why that is not known (core.heading: up
to ~200 characters, an error's text included; the column held 64). ``attractor`` becomes
VARCHAR(24), ``detail`` TEXT. Every row is kept as it was.

The downgrade narrows them again: an attractor that does not fit (unstable-fixed-point)
becomes NULL, as a run computed before 0003 reads, and a detail is cut to 64 characters.
The regime ``undetermined``, which an older slopetui does not know (its plots refuse a
regime they cannot draw), becomes NULL too; those runs keep their status.
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision: str = "0010"
down_revision: str | None = "0009"
branch_labels = None
depends_on = None


def upgrade() -> None:
    with op.batch_alter_table("runs", schema=None) as batch_op:
        batch_op.alter_column("attractor", existing_type=sa.String(length=16),
                              type_=sa.String(length=24), existing_nullable=True)
        batch_op.alter_column("detail", existing_type=sa.String(length=64), type_=sa.Text(),
                              existing_nullable=True)


def downgrade() -> None:
    op.execute("UPDATE runs SET attractor = NULL WHERE length(attractor) > 16")
    op.execute("UPDATE runs SET regime = NULL WHERE regime = 'undetermined'")
    op.execute("UPDATE runs SET detail = substr(detail, 1, 64) WHERE length(detail) > 64")
    with op.batch_alter_table("runs", schema=None) as batch_op:
        batch_op.alter_column("detail", existing_type=sa.Text(), type_=sa.String(length=64),
                              existing_nullable=True)
        batch_op.alter_column("attractor", existing_type=sa.String(length=24),
                              type_=sa.String(length=16), existing_nullable=True)
