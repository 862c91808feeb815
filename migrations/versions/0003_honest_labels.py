"""Honest labels: the return of an orbit, its attractor, whether it settled, and flags.

Revision ID: 0003
Revises: 0002
Create Date: 2026-12-01 18:30:00.000000

Only nullable columns are added: runs computed before this revision read NULL there (the
engine that computed them did not measure these), and their results stay as they were
(a new engine has a new digest, so the cache recomputes rather than reuse them).
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision: str = '0003'
down_revision: str | None = '0002'
branch_labels = None
depends_on = None


def upgrade() -> None:
    with op.batch_alter_table('runs', schema=None) as batch_op:
        batch_op.add_column(sa.Column('maxima_per_period', sa.Integer(), nullable=True))
        batch_op.add_column(sa.Column('attractor', sa.String(length=16), nullable=True))
        batch_op.add_column(sa.Column('settled', sa.Boolean(), nullable=True))
        batch_op.add_column(sa.Column('flags', sa.String(length=160), nullable=True))


def downgrade() -> None:
    with op.batch_alter_table('runs', schema=None) as batch_op:
        batch_op.drop_column('flags')
        batch_op.drop_column('settled')
        batch_op.drop_column('attractor')
        batch_op.drop_column('maxima_per_period')
