"""Adaptive phase diagrams: inferred runs, refinement levels of runs and sweeps.

Revision ID: 0002
Revises: 0001
Create Date: 2026-12-02 10:00:00.000000

Only columns are added, and the NOT NULL booleans carry a server default, so the rows
already stored read false (computed runs; sweeps of every point).

The defaults are the literal '0' (false on SQLite and PostgreSQL alike), not
``sa.false()``: with a SQL expression as default, Alembic's batch mode on SQLite
rebuilds the table instead of ALTER TABLE ADD COLUMN, and rebuilding ``sweeps`` drops
the old table, which with foreign keys on cascades to (deletes) every run.
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision: str = '0002'
down_revision: str | None = '0001'
branch_labels = None
depends_on = None


def upgrade() -> None:
    with op.batch_alter_table('sweeps', schema=None) as batch_op:
        batch_op.add_column(sa.Column('adaptive_levels', sa.Integer(), nullable=True))
        batch_op.add_column(sa.Column('level', sa.Integer(), nullable=True))
        batch_op.add_column(sa.Column('refined', sa.Boolean(), server_default='0',
                                      nullable=False))
    with op.batch_alter_table('runs', schema=None) as batch_op:
        batch_op.add_column(sa.Column('level', sa.Integer(), nullable=True))
        batch_op.add_column(sa.Column('inferred', sa.Boolean(), server_default='0',
                                      nullable=False))


def downgrade() -> None:
    with op.batch_alter_table('runs', schema=None) as batch_op:
        batch_op.drop_column('inferred')
        batch_op.drop_column('level')
    with op.batch_alter_table('sweeps', schema=None) as batch_op:
        batch_op.drop_column('refined')
        batch_op.drop_column('level')
        batch_op.drop_column('adaptive_levels')
