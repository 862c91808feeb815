"""The arguments of ``slopetui db``."""

from __future__ import annotations

import argparse

from slopetui.cli.arguments import add_db_option
from slopetui.ops import local_server

#: PostgreSQL needs a few connections for itself (superuser_reserved_connections = 3);
#: beyond 10 000 each connection's memory adds up to more than a node has.
MAX_CONNECTIONS_RANGE = (10, 10_000)


def declare(sub: argparse._SubParsersAction) -> None:
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
    down = actions.add_parser(
        "downgrade", help="migrate the database back to an older schema revision",
        description="Migrate back to REV (for an older slopetui), after a backup: a SQLite "
                    "file is copied aside (FILE.bak-REV), a PostgreSQL database is dumped "
                    "with pg_dump into a file of mode 600 (refused without pg_dump unless "
                    "--no-backup). Asks first, naming what the downgrade drops (the "
                    "continuations, hysteresis sweeps... an older schema has no place for). "
                    "Any command of this slopetui upgrades it again.")
    down.add_argument("revision", metavar="REV",
                      help="an older revision (`slopetui db current` shows the database's), "
                           "or base (no tables)")
    down.add_argument("--yes", action="store_true", help="do not ask for confirmation")
    down.add_argument("--no-backup", action="store_true",
                      help="PostgreSQL: downgrade without the pg_dump backup (a SQLite file "
                           "is always copied)")
    add_db_option(down)
    _declare_serve(actions)
    rev = actions.add_parser("revision", help="(developers) autogenerate a migration from "
                                              "the models, against an up-to-date --db")
    rev.add_argument("-m", "--message", required=True)
    add_db_option(rev)


def _declare_serve(actions: argparse._SubParsersAction) -> None:
    ls = local_server
    p = actions.add_parser(
        "serve", help="run a PostgreSQL server of your own for the workers (no root)",
        description="Start a PostgreSQL server owned by you (initdb the first time, then "
                    "pg_ctl; no root, no administrator) with a database for slopetui at the "
                    "current schema, print the URL to give the workers, and stay in the "
                    "foreground: Ctrl-C, SIGTERM or SIGHUP stops the server (pg_ctl stop -m "
                    "fast) and exits 0; exit 1 if the server stops on its own, 2 for bad "
                    "options. Later starts reuse DIR: same data, password and (unless "
                    "changed) port. Over the network only the role slopetui is let in, with "
                    "its random password (DIR/password, mode 600), by scram-sha-256. "
                    "A second role, slopetui_read, only reads (SELECT; it cannot signal the "
                    "workers' connections nor take their locks): its URL is in DIR/read-url, "
                    "for colleagues and for $SLOPETUI_READ_DB, under which `slopetui sql` "
                    "and the console run (docs/store.md: the same role on another server). "
                    "SIGHUP is left ignored under nohup. Needs PostgreSQL's server programs "
                    "(apt install postgresql, or conda install -c conda-forge postgresql).")
    p.add_argument("--dir", metavar="DIR",
                   help=f"the server's folder, made (mode 700) the first time (default "
                        f"{ls.default_folder()}); the cluster is DIR/data")
    p.add_argument("--port", metavar="PORT",
                   help=f"TCP port, 1024 to 65535 (default: the last start's, else "
                        f"{ls.DEFAULT_PORT})")
    p.add_argument("--listen", metavar="ADDR",
                   help="addresses to listen on, comma-separated (default: the last start's, "
                        f"else '{ls.DEFAULT_LISTEN}': every interface)")
    p.add_argument("--max-connections", metavar="N",
                   help=f"connections the server accepts, {MAX_CONNECTIONS_RANGE[0]} to "
                        f"{MAX_CONNECTIONS_RANGE[1]} (default: the last start's, else "
                        f"{ls.DEFAULT_MAX_CONNECTIONS}; a worker pool holds 2 by default)")
    p.add_argument("--pg-bin", metavar="DIR",
                   help="folder of PostgreSQL's initdb, pg_ctl and postgres (default: "
                        "PATH's, else the newest /usr/lib/postgresql/*/bin)")
    other = p.add_mutually_exclusive_group()
    other.add_argument("--stop", action="store_true",
                       help="stop the server of DIR (asks its `slopetui db serve` to stop, "
                            "or pg_ctl stop -m fast if none runs it) and wait")
    other.add_argument("--status", action="store_true",
                       help="say whether the server of DIR runs (exit 0 if it accepts "
                            "connections, else 1)")
    other.add_argument("--url", action="store_true",
                       help="print the workers' URL of DIR's last start (for scripts: "
                            "export SLOPETUI_DB=$(slopetui db serve --url))")
