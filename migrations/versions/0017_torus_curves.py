"""Torus (Neimark-Sacker) curves as jobs: ``curves.kind`` may be ``ns``.

Revision ID: 0017
Revises: 0016
Create Date: 2026-12-04 02:30:00

The CHECK on ``curves.kind`` allows 'ns' besides 'fold', 'hopf' and 'pd' (a torus curve
from the first torus bifurcation of the branch in ``param`` up to ``branch_end``, as a
'pd' curve's). Its points go in ``curve_points`` as the others' do: no new column (a
torus point's resume state holds its border and kappa; its ``curvature`` is NULL). On
SQLite a CHECK cannot be altered in place: the table is rebuilt, keeping 0009's
AUTOINCREMENT and the largest id ever handed out (as 0010 does for runs); the other
named CHECKs and the index are carried over by the batch's reflection.

The downgrade deletes the torus curves with their points and codimension-two points
(an older slopetui has no kind for them; downgrade_losses names them) and puts the older
CHECK back.
"""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

from alembic import op
from alembic.operations import BatchOperations

revision: str = "0017"
down_revision: str | None = "0016"
branch_labels = None
depends_on = None


@contextmanager
def _curves_rebuilt() -> Iterator[BatchOperations]:
    """A batch on curves that keeps its AUTOINCREMENT and largest id on SQLite (see
    0010's ``_runs_rebuilt``, the same for runs)."""
    sqlite = op.get_bind().dialect.name == "sqlite"
    seq = (op.get_bind().exec_driver_sql(
        "SELECT seq FROM sqlite_sequence WHERE name = 'curves'").scalar() if sqlite else None)
    with op.batch_alter_table("curves", schema=None,
                              table_kwargs={"sqlite_autoincrement": True}) as batch_op:
        yield batch_op
    if seq is not None:
        op.execute("DELETE FROM sqlite_sequence WHERE name = 'curves'")
        op.execute(f"INSERT INTO sqlite_sequence (name, seq) SELECT 'curves', "
                   f"max({int(seq)}, coalesce(max(id), 0)) FROM curves")


def _kinds(kinds: str) -> None:
    with _curves_rebuilt() as batch_op:
        batch_op.drop_constraint(op.f("ck_curves_kind"), type_="check")
        batch_op.create_check_constraint(op.f("ck_curves_kind"), f"kind IN ({kinds})")


def upgrade() -> None:
    _kinds("'fold', 'hopf', 'pd', 'ns'")


def downgrade() -> None:
    # the migration runs with SQLite's foreign keys off: no cascade, each table by hand
    for table in ("curve_bifurcations", "curve_points"):
        op.execute(f"DELETE FROM {table} WHERE curve_id IN "
                   "(SELECT id FROM curves WHERE kind = 'ns')")
    op.execute("DELETE FROM curves WHERE kind = 'ns'")
    _kinds("'fold', 'hopf', 'pd'")
