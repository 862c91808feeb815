"""``slopetui db upgrade|downgrade|current|check|revision``: the schema and health of the
store."""

from __future__ import annotations

import argparse
import sys
from typing import TYPE_CHECKING

from slopetui.cli.options import UsageError, add_db_option

if TYPE_CHECKING:
    from slopetui.store.database import Database


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("db", help="migrate, check or inspect the database",
                       description="Migrations also apply automatically whenever a "
                                   "command opens the database; a SQLite store is copied "
                                   "aside (FILE.bak-REV) before any change of schema.")
    actions = p.add_subparsers(dest="db_action", metavar="ACTION", required=True)
    for name, help_ in (("upgrade", "migrate the database to the current schema"),
                        ("current", "print the database's schema revision and location"),
                        ("check", "check the file's integrity and its foreign keys "
                                  "(exit 1 if damaged)")):
        a = actions.add_parser(name, help=help_, description=help_)
        add_db_option(a)
        a.set_defaults(handler=handle)
    down = actions.add_parser(
        "downgrade", help="migrate the database back to an older schema revision",
        description="Migrate back to REV (for an older slopetui), after a backup copy of a "
                    "SQLite file. Any command of this slopetui upgrades it again.")
    down.add_argument("revision", metavar="REV",
                      help="an older revision (`slopetui db current` shows the database's), "
                           "or base (no tables)")
    down.add_argument("--yes", action="store_true", help="do not ask for confirmation")
    add_db_option(down)
    down.set_defaults(handler=handle)
    rev = actions.add_parser("revision", help="(developers) autogenerate a migration from "
                                              "the models, against an up-to-date --db")
    rev.add_argument("-m", "--message", required=True)
    add_db_option(rev)
    rev.set_defaults(handler=handle)


def _confirm(db: Database, revision: str, assume_yes: bool) -> None:
    if assume_yes:
        return
    question = (f"migrate {db.display_url} back to revision {revision}? "
                f"{'Every table is dropped. ' if revision == 'base' else ''}"
                f"{'A backup copy is made first. ' if db.path else 'No backup copy is made (use pg_dump). '}"
                "[y/N] ")
    if not sys.stdin.isatty():
        raise UsageError("a downgrade needs confirmation: add --yes")
    if input(question).strip().lower() not in ("y", "yes"):
        raise UsageError("not confirmed; nothing was changed")


def _check(db: Database) -> int:
    from slopetui.store.integrity import integrity_problems

    problems = integrity_problems(db)
    if db.path is None:
        print(f"{db.display_url}: not a SQLite file; PostgreSQL checks its own pages")
        return 0
    if not problems:
        print(f"{db.path}: ok (integrity and foreign keys)")
        return 0
    print(f"{db.path}: DAMAGED, {len(problems)} problem{'s' if len(problems) > 1 else ''}:")
    for line in problems:
        print(f"  {line}")
    print(f"restore a backup ({db.path.name}.bak-* beside it) or copy out what is readable "
          "with the sqlite3 shell's .recover")
    return 1


def handle(args: argparse.Namespace) -> int:
    # Alembic here, not at the top: it costs ~0.2 s that `slopetui --help` should not pay
    from slopetui.store.database import Database, StoreError
    from slopetui.store.migrate import (
        alembic_config,
        current_revision,
        downgrade,
        head_revision,
        upgrade,
    )

    if args.db_action == "upgrade":
        db = Database(args.db)
        before, after = upgrade(db)
        print(f"{db.display_url}: {before or 'empty'} -> {after}"
              if before != after else f"{db.display_url}: already at {after}")
    elif args.db_action == "downgrade":
        db = Database(args.db)
        _confirm(db, args.revision, args.yes)
        before, after, copy = downgrade(db, args.revision)
        print(f"{db.display_url}: {before} -> {after}"
              + (f"; backup copy {copy}" if copy else ""))
        print("note: any command of this slopetui upgrades it again")
    elif args.db_action == "current":
        db = Database(args.db)
        rev = current_revision(db)
        state = "current" if rev == head_revision() else f"head is {head_revision()}"
        print(f"{db.display_url}: revision {rev or 'none (empty)'} ({state})")
    elif args.db_action == "check":
        try:
            db = Database(args.db)
        except StoreError as exc:  # a file SQLite cannot even open is damaged too
            print(exc)
            return 1
        return _check(db)
    else:
        from alembic import command

        from slopetui.store.open import open_store
        db = open_store(args.db)  # autogenerate compares the models with the head schema
        command.revision(alembic_config(db), message=args.message, autogenerate=True)
    return 0
