"""``slopetui db upgrade|current|revision``: the schema of the store."""

from __future__ import annotations

import argparse

from slopetui.cli.options import add_db_option
from slopetui.store.database import Database
from slopetui.store.migrate import (
    alembic_config,
    current_revision,
    head_revision,
    upgrade,
)


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("db", help="migrate or inspect the database schema",
                       description="Migrations also apply automatically whenever a "
                                   "command opens the database.")
    actions = p.add_subparsers(dest="db_action", metavar="ACTION", required=True)
    for name, help_ in (("upgrade", "migrate the database to the current schema"),
                        ("current", "print the database's schema revision and location")):
        a = actions.add_parser(name, help=help_, description=help_)
        add_db_option(a)
        a.set_defaults(handler=handle)
    rev = actions.add_parser("revision", help="(developers) autogenerate a migration from "
                                              "the models, against an up-to-date --db")
    rev.add_argument("-m", "--message", required=True)
    add_db_option(rev)
    rev.set_defaults(handler=handle)


def handle(args: argparse.Namespace) -> int:
    if args.db_action == "upgrade":
        db = Database(args.db, upgrade=False)
        before, after = upgrade(db)
        print(f"{db.display_url}: {before or 'empty'} -> {after}"
              if before != after else f"{db.display_url}: already at {after}")
    elif args.db_action == "current":
        db = Database(args.db, upgrade=False)
        rev = current_revision(db)
        state = "current" if rev == head_revision() else f"head is {head_revision()}"
        print(f"{db.display_url}: revision {rev or 'none (empty)'} ({state})")
    else:
        from alembic import command
        db = Database(args.db)
        command.revision(alembic_config(db), message=args.message, autogenerate=True)
    return 0
