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

On SQLite both ways rebuild the runs table; the rebuild keeps 0009's AUTOINCREMENT and
the largest id ever handed out (``_runs_rebuilt``).
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

import sqlalchemy as sa
from alembic import op
from alembic.operations import BatchOperations

revision: str = "0010"
down_revision: str | None = "0009"
branch_labels = None
depends_on = None


@contextmanager
def _runs_rebuilt() -> Iterator[BatchOperations]:
    """A batch on runs that keeps what 0009 gave it on SQLite, where a changed column type
    rebuilds the table from its reflection, which knows no AUTOINCREMENT: the table option
    again, and the largest id ever handed out (the copy would seed sqlite_sequence with the
    largest id left, below the ids of newest runs deleted before)."""
    sqlite = op.get_bind().dialect.name == "sqlite"
    seq = (op.get_bind().exec_driver_sql(
        "SELECT seq FROM sqlite_sequence WHERE name = 'runs'").scalar() if sqlite else None)
    with op.batch_alter_table("runs", schema=None,
                              table_kwargs={"sqlite_autoincrement": True}) as batch_op:
        yield batch_op
    if seq is not None:
        op.execute("DELETE FROM sqlite_sequence WHERE name = 'runs'")
        op.execute(f"INSERT INTO sqlite_sequence (name, seq) SELECT 'runs', "
                   f"max({int(seq)}, coalesce(max(id), 0)) FROM runs")


def upgrade() -> None:
    with _runs_rebuilt() as batch_op:
        batch_op.alter_column("attractor", existing_type=sa.String(length=16),
                              type_=sa.String(length=24), existing_nullable=True)
        batch_op.alter_column("detail", existing_type=sa.String(length=64), type_=sa.Text(),
                              existing_nullable=True)


def downgrade() -> None:
    op.execute("UPDATE runs SET attractor = NULL WHERE length(attractor) > 16")
    op.execute("UPDATE runs SET regime = NULL WHERE regime = 'undetermined'")
    op.execute("UPDATE runs SET detail = substr(detail, 1, 64) WHERE length(detail) > 64")
    with _runs_rebuilt() as batch_op:
        batch_op.alter_column("detail", existing_type=sa.Text(), type_=sa.String(length=64),
                              existing_nullable=True)
        batch_op.alter_column("attractor", existing_type=sa.String(length=24),
                              type_=sa.String(length=16), existing_nullable=True)
