"""Initial schema: sweeps, runs (the jobs of the queue) and workers.

Revision ID: 0001
Revises: (none)
Create Date: 2026-11-22 01:43:17.311441
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision: str = '0001'
down_revision: str | None = None
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.create_table('sweeps',
    sa.Column('id', sa.Integer(), nullable=False),
    sa.Column('name', sa.String(length=200), nullable=False),
    sa.Column('spec', sa.JSON(), nullable=False),
    sa.Column('x_param', sa.String(length=8), nullable=False),
    sa.Column('y_param', sa.String(length=8), nullable=True),
    sa.Column('n_runs', sa.Integer(), nullable=False),
    sa.Column('status', sa.String(length=16), nullable=False),
    sa.Column('created_at', sa.DateTime(), server_default=sa.text('(CURRENT_TIMESTAMP)'), nullable=False),
    sa.CheckConstraint("status IN ('active', 'paused', 'cancelled')", name=op.f('ck_sweeps_status')),
    sa.PrimaryKeyConstraint('id', name=op.f('pk_sweeps'))
    )
    op.create_table('runs',
    sa.Column('id', sa.Integer(), nullable=False),
    sa.Column('sweep_id', sa.Integer(), nullable=False),
    sa.Column('ix', sa.Integer(), nullable=False),
    sa.Column('iy', sa.Integer(), nullable=False),
    sa.Column('a', sa.Double(), nullable=False),
    sa.Column('b', sa.Double(), nullable=False),
    sa.Column('c', sa.Double(), nullable=False),
    sa.Column('d', sa.Double(), nullable=False),
    sa.Column('k', sa.Double(), nullable=False),
    sa.Column('v', sa.Double(), nullable=False),
    sa.Column('tau', sa.Double(), nullable=False),
    sa.Column('delta', sa.Double(), nullable=False),
    sa.Column('method', sa.String(length=8), nullable=False),
    sa.Column('dt', sa.Double(), nullable=False),
    sa.Column('t_end', sa.Double(), nullable=False),
    sa.Column('window', sa.Double(), nullable=False),
    sa.Column('lyap', sa.Boolean(), nullable=False),
    sa.Column('engine', sa.String(length=16), nullable=False),
    sa.Column('cache_key', sa.String(length=64), nullable=False),
    sa.Column('status', sa.String(length=16), nullable=False),
    sa.Column('worker_id', sa.String(length=128), nullable=True),
    sa.Column('attempts', sa.Integer(), nullable=False),
    sa.Column('created_at', sa.DateTime(), server_default=sa.text('(CURRENT_TIMESTAMP)'), nullable=False),
    sa.Column('started_at', sa.DateTime(), nullable=True),
    sa.Column('heartbeat_at', sa.DateTime(), nullable=True),
    sa.Column('finished_at', sa.DateTime(), nullable=True),
    sa.Column('error', sa.Text(), nullable=True),
    sa.Column('cached_from', sa.Integer(), nullable=True),
    sa.Column('regime', sa.String(length=16), nullable=True),
    sa.Column('detail', sa.String(length=64), nullable=True),
    sa.Column('lambda_max', sa.Double(), nullable=True),
    sa.Column('lambda_err', sa.Double(), nullable=True),
    sa.Column('amplitude', sa.Double(), nullable=True),
    sa.Column('period', sa.Double(), nullable=True),
    sa.Column('period_count', sa.Integer(), nullable=True),
    sa.Column('peaks', sa.JSON(), nullable=True),
    sa.Column('frequency', sa.Double(), nullable=True),
    sa.Column('drift', sa.Double(), nullable=True),
    sa.Column('zero_one_k', sa.Double(), nullable=True),
    sa.Column('t_blowup', sa.Double(), nullable=True),
    sa.Column('runtime_s', sa.Double(), nullable=True),
    sa.CheckConstraint("status IN ('queued', 'running', 'done', 'failed', 'cancelled')", name=op.f('ck_runs_status')),
    sa.CheckConstraint('attempts >= 0', name=op.f('ck_runs_attempts')),
    sa.ForeignKeyConstraint(['cached_from'], ['runs.id'], name=op.f('fk_runs_cached_from_runs'), ondelete='SET NULL'),
    sa.ForeignKeyConstraint(['sweep_id'], ['sweeps.id'], name=op.f('fk_runs_sweep_id_sweeps'), ondelete='CASCADE'),
    sa.PrimaryKeyConstraint('id', name=op.f('pk_runs'))
    )
    with op.batch_alter_table('runs', schema=None) as batch_op:
        batch_op.create_index(batch_op.f('ix_runs_cache_key_status'), ['cache_key', 'status'], unique=False)
        batch_op.create_index(batch_op.f('ix_runs_regime_tau'), ['regime', 'tau'], unique=False)
        batch_op.create_index(batch_op.f('ix_runs_status_id'), ['status', 'id'], unique=False)
        batch_op.create_index(batch_op.f('ix_runs_sweep_id_regime'), ['sweep_id', 'regime'], unique=False)
        batch_op.create_index(batch_op.f('ix_runs_sweep_id_status'), ['sweep_id', 'status'], unique=False)

    op.create_table('workers',
    sa.Column('id', sa.String(length=128), nullable=False),
    sa.Column('host', sa.String(length=255), nullable=False),
    sa.Column('pid', sa.Integer(), nullable=False),
    sa.Column('started_at', sa.DateTime(), server_default=sa.text('(CURRENT_TIMESTAMP)'), nullable=False),
    sa.Column('heartbeat_at', sa.DateTime(), server_default=sa.text('(CURRENT_TIMESTAMP)'), nullable=False),
    sa.Column('stopped_at', sa.DateTime(), nullable=True),
    sa.Column('run_id', sa.Integer(), nullable=True),
    sa.Column('jobs_done', sa.Integer(), nullable=False),
    sa.ForeignKeyConstraint(['run_id'], ['runs.id'], name=op.f('fk_workers_run_id_runs'), ondelete='SET NULL'),
    sa.PrimaryKeyConstraint('id', name=op.f('pk_workers'))
    )


def downgrade() -> None:
    op.drop_table('workers')
    with op.batch_alter_table('runs', schema=None) as batch_op:
        batch_op.drop_index(batch_op.f('ix_runs_sweep_id_status'))
        batch_op.drop_index(batch_op.f('ix_runs_sweep_id_regime'))
        batch_op.drop_index(batch_op.f('ix_runs_status_id'))
        batch_op.drop_index(batch_op.f('ix_runs_regime_tau'))
        batch_op.drop_index(batch_op.f('ix_runs_cache_key_status'))

    op.drop_table('runs')
    op.drop_table('sweeps')
