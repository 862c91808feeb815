"""Attractors, not windows: each run's certificate, its orbit's multipliers and slips, the
accuracy of its scheme at its step, and its Lyapunov spectrum.

Revision ID: 0012
Revises: 0011
Create Date: 2026-12-03 13:20:00

New result columns of ``runs`` (core.result_fields gives their meaning):
- ``certified`` (boolean) and ``certificate`` (text: how the attractor was certified, or
  why it was not): NULL for runs computed before this revision, which were never tried;
- ``multipliers`` (JSON list of [re, im]): the certified orbit's Floquet multipliers;
- ``slips`` (integer): slips (maxima of m_y) in one period of the certified orbit;
- ``dt_error`` (float, NaN as NULL): the run's estimated relative error at its dt;
- ``spectrum`` and ``spectrum_err`` (JSON lists): the top Lyapunov exponents, with the
  m_x shift quotiented out, and their standard errors (``run --spectrum N``).

Plain ADD COLUMN, nullable, which SQLite does in place: runs keeps 0009's AUTOINCREMENT
and sqlite_sequence (no rebuild). The downgrade drops them, in place too (SQLite >= 3.35).
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision: str = "0012"
down_revision: str | None = "0011"
branch_labels = None
depends_on = None

#: The new columns of runs, in order.
COLUMNS: tuple[tuple[str, sa.types.TypeEngine], ...] = (
    ("certified", sa.Boolean()),
    ("certificate", sa.Text()),
    ("multipliers", sa.JSON()),
    ("slips", sa.Integer()),
    ("dt_error", sa.Double()),
    ("spectrum", sa.JSON()),
    ("spectrum_err", sa.JSON()),
)


def upgrade() -> None:
    for name, type_ in COLUMNS:
        op.add_column("runs", sa.Column(name, type_, nullable=True))


def downgrade() -> None:
    for name, _ in COLUMNS[::-1]:
        op.drop_column("runs", name)
