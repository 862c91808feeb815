"""Measurements' NaN as NULL on PostgreSQL too (slopetui.store.column_types.Measure).

Revision ID: 0007
Revises: 0006
Create Date: 2026-12-02 00:40:00

PostgreSQL orders NaN above every number, so `lambda_max > 0` held for a run whose
lambda_max is undefined; SQLite never stored NaN (it has none: NULL). The NaN that
PostgreSQL stores already are set to NULL, which slopetui reads back as NaN: nothing a
reader of the runs sees changes, only what SQL comparisons say. SQLite: nothing to do.
The downgrade leaves NULL (an older slopetui reads it as NaN too).
"""

from __future__ import annotations

from alembic import op

revision: str = "0007"
down_revision: str | None = "0006"
branch_labels = None
depends_on = None

#: The Measure columns of each table (slopetui.store.models).
MEASURES = {
    "runs": ("lambda_max", "lambda_err", "amplitude", "period", "frequency", "drift",
             "zero_one_k"),
    "hysteresis_points": ("amplitude", "growth"),
}


def upgrade() -> None:
    if op.get_bind().dialect.name != "postgresql":
        return
    for table, columns in MEASURES.items():
        for column in columns:
            op.execute(f"UPDATE {table} SET {column} = NULL WHERE {column} = 'NaN'::float8")


def downgrade() -> None:
    pass
