"""Ids are never reused: AUTOINCREMENT on SQLite for sweeps, runs, continuations and
hysteresis sweeps.

Revision ID: 0009
Revises: 0008
Create Date: 2026-12-03 10:10:00

An INTEGER PRIMARY KEY without AUTOINCREMENT takes max(id) + 1: after the newest sweep was
deleted, the next submit was that sweep again, and its runs took the deleted runs' ids,
so a notebook's "run 144", a file sweep-3.pdf or a CSV joined later pointed at other data.
With AUTOINCREMENT, SQLite keeps the largest id ever handed out in sqlite_sequence and
goes on above it. PostgreSQL's sequences never go back: nothing to do there.

SQLite cannot add AUTOINCREMENT to a table: each of the four is rebuilt (batch mode,
recreate="always": a new table, every row copied with its id, DROP, rename), with its
indexes, foreign keys and named CHECK constraints, and with the foreign keys off
(migrations/env.py). The primary key loses its name (pk_<table>) on SQLite, which writes
AUTOINCREMENT on the column, where a constraint has no name; SQLite gives that name no
meaning, and PostgreSQL keeps its pk_<table>. Copying the rows with their ids seeds sqlite_sequence with each
table's largest id; this script writes it once more, so that it holds even for a table
whose newest rows were deleted before. Ids deleted before this revision above the largest
id left cannot be known: those may be handed out once more.

The other tables' keys are not handed out: workers are named host:pid, branch and
hysteresis points and bifurcations by (their job, idx), initial states by digest.

The downgrade rebuilds the four tables without AUTOINCREMENT (every row kept), and an
older slopetui reuses the largest ids again.
"""

from __future__ import annotations

from alembic import op

revision: str = "0009"
down_revision: str | None = "0008"
branch_labels = None
depends_on = None

#: The tables whose ids the commands take and print (models.py: sqlite_autoincrement).
#: sweeps before runs: the order does not matter with the foreign keys off, but it is the
#: order of the foreign keys.
TABLES = ("sweeps", "runs", "continuations", "hysteresis_sweeps")


def _rebuild(autoincrement: bool) -> None:
    if op.get_bind().dialect.name != "sqlite":
        return
    for table in TABLES:
        with op.batch_alter_table(table, recreate="always",
                                  table_kwargs={"sqlite_autoincrement": autoincrement}) as batch:
            if not autoincrement:
                # SQLite writes AUTOINCREMENT on the column itself, where the primary key
                # has no name: the downgrade gives it back the name 0001 gave it
                batch.create_primary_key(f"pk_{table}", ["id"])
    if autoincrement:
        for table in TABLES:
            # (what the copy already did, said once more: the largest id of each table
            # that has rows; an empty table starts from 1 as before)
            op.execute(f"DELETE FROM sqlite_sequence WHERE name = '{table}'")
            op.execute(f"INSERT INTO sqlite_sequence (name, seq) "
                       f"SELECT '{table}', max(id) FROM {table} HAVING count(*) > 0")


def upgrade() -> None:
    _rebuild(autoincrement=True)


def downgrade() -> None:
    _rebuild(autoincrement=False)
