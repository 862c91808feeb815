"""A queued continuation may start at any Hopf point of the rest state, not only the
first: the index of its Hopf point.

Revision ID: 0015
Revises: 0014
Create Date: 2026-12-03 22:40:00

New column of ``continuations``: ``hopf_branch`` (integer): for a branch from a Hopf
point ("hopf" start) the index n of the root pair whose crossing it starts at (1 the
first, core.stability's omega_n), NULL for a branch from a simulated orbit. Backfilled
with 1 for the "hopf" rows: before this revision a queued continuation could only start
at the first Hopf point. Plain ADD COLUMN, in place on SQLite (continuations keeps 0009's
AUTOINCREMENT); no CHECK on its values, as a CHECK would rebuild the table on SQLite.

The downgrade drops it, in place too (SQLite >= 3.35). An older slopetui reads a
continuation from a later Hopf point as one from the first: its done points stay, under a
start that no longer names them, and a queued or running one would be computed from the
wrong Hopf point. Those are failed first, with the reason as their error.
"""

from __future__ import annotations

import sqlalchemy as sa
from alembic import op

from slopetui.store.db_time import db_now

revision: str = "0015"
down_revision: str | None = "0014"
branch_labels = None
depends_on = None

#: What a queued or running continuation from a later Hopf point is failed with on the way
#: down (an older worker would start it at the first).
DOWNGRADE_ERROR = ("not computed: the store was downgraded below revision 0015, which has no "
                   "place for its Hopf point's index (it would start at the first)")


def upgrade() -> None:
    op.add_column("continuations", sa.Column("hopf_branch", sa.Integer(), nullable=True))
    op.execute("UPDATE continuations SET hopf_branch = 1 WHERE start = 'hopf'")


def downgrade() -> None:
    rows = sa.table("continuations", sa.column("status"), sa.column("error"),
                    sa.column("finished_at"), sa.column("hopf_branch"))
    op.execute(rows.update()
               .where(rows.c.hopf_branch > 1, rows.c.status.in_(("queued", "running")))
               .values(status="failed", error=DOWNGRADE_ERROR, finished_at=db_now()))
    op.drop_column("continuations", "hopf_branch")
