"""A run stops where its attractor is certified: the stop rule it ran under and when it
stopped.

Revision ID: 0013
Revises: 0012
Create Date: 2026-12-03 17:10:00

New columns of ``runs``:
- ``stop`` (text, not null, server default 't_end'): the stop rule (core.solve.STOPS), an
  input like method and history; every run before this revision ran to its t_end (the
  paper's protocol), which the default says of them;
- ``t_stop`` (float, NULL before the run is done): when the run stopped
  (core.result_fields). Backfilled for the done runs from what they kept: where the
  explicit scheme blew up, t_blowup, unless the stiff scheme took the run over
  (``stiff-fallback``) and ran it to t_end; a fallback that diverged too kept no time of
  its own, and stays NULL (unknown); every other done run stopped at its t_end.
  Inferred runs computed nothing and keep NULL.

Plain ADD COLUMN, which SQLite does in place (a NOT NULL column with a constant default
is allowed): runs keeps 0009's AUTOINCREMENT and sqlite_sequence (no rebuild). No CHECK on
stop's values, as there is none on method or history: a CHECK would rebuild the table on
SQLite. The downgrade drops both, in place too (SQLite >= 3.35).
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

revision: str = "0013"
down_revision: str | None = "0012"
branch_labels = None
depends_on = None

#: t_stop of the done runs, from the columns they kept (see the docstring).
BACKFILL = """
UPDATE runs SET t_stop = CASE
    WHEN flags LIKE '%stiff-fallback%' AND attractor = 'divergent' THEN NULL
    WHEN flags LIKE '%stiff-fallback%' THEN t_end
    ELSE coalesce(t_blowup, t_end) END
WHERE status = 'done' AND NOT inferred
"""


def upgrade() -> None:
    op.add_column("runs", sa.Column("stop", sa.Text(), nullable=False, server_default="t_end"))
    op.add_column("runs", sa.Column("t_stop", sa.Double(), nullable=True))
    op.execute(BACKFILL)


def downgrade() -> None:
    op.drop_column("runs", "t_stop")
    op.drop_column("runs", "stop")
