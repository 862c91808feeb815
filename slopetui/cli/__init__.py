# PYTHON_ARGCOMPLETE_OK
"""The ``slopetui`` command line: one module per subcommand, wired here."""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Sequence

from slopetui import __version__
from slopetui.cli import (
    branch,
    cluster,
    completion,
    continuation,
    control,
    db,
    delete,
    example,
    figure,
    hysteresis,
    nblock,
    orbit,
    reproduce,
    run,
    runs,
    show,
    sql,
    status,
    submit,
    worker,
    workers,
)
from slopetui.store.failures import DatabaseFailure, StoreError
from slopetui.store.location import checked_url
from slopetui.store.url_text import holds_password

#: Errors that are the user's input or environment, not a bug: one line, no traceback,
#: exit 2. Named by module rather than imported: a class whose module was never loaded
#: cannot have raised, and importing them all (the store, numpy) would cost every
#: command, `--help` included, the imports only some need (slopetui.cli.options).
USER_ERRORS = (("core.params", "ParameterError"), ("core.orbit", "OrbitError"), ("slopetui.sweeps.spec", "SpecError"),
               ("slopetui.store.failures", "StoreError"),
               ("slopetui.sweeps.control", "UnknownSweep"), ("slopetui.cli.options", "UsageError"))
#: The commands that run for hours (a pool, the application; None is the application):
#: a password on their command line is in `ps` all that time, so they warn of it.
LONG_LIVED = (None, "worker")


def loaded(names: tuple[tuple[str, str], ...]) -> tuple[type[BaseException], ...]:
    """The classes of ``names`` whose modules are loaded."""
    return tuple(getattr(sys.modules[module], name) for module, name in names
                 if module in sys.modules)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="slopetui",
        description="Simulate, sweep and classify the mean-field spring-block landslide model. "
                    "Without a COMMAND: open the terminal application.",
    )
    parser.add_argument("--version", action="version", version=f"slopetui {__version__}")
    parser.add_argument("--db", dest="tui_db", metavar="URL",
                        help="with no COMMAND: open the application on this database")
    parser.add_argument("--no-workers", action="store_true",
                        help="with no COMMAND: do not start or attach to a local worker pool")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for module in (run, orbit, continuation, branch, hysteresis, submit, example, status, show, figure, runs,
                   control, delete, sql, worker, workers, db, cluster, nblock, reproduce, completion):
        module.register(sub)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    if "_ARGCOMPLETE" in os.environ:  # a shell asks for completions (slopetui completion)
        completion.enable(parser)
    args = parser.parse_args(argv)
    # --db '' or in-memory SQLite: refused before anything opens or creates a store.
    # `cluster` names a server for other hosts and refuses every SQLite URL itself.
    url = args.tui_db if args.command is None else getattr(args, "db", None)
    if url is not None and args.command != "cluster":
        try:
            checked_url(url)
        except StoreError as exc:
            print(f"slopetui{' ' + args.command if args.command else ''}: error: {exc}",
                  file=sys.stderr)
            return 2
        if args.command in LONG_LIVED and holds_password(url):  # the user's choice; not silent
            print("slopetui: warning: the password in --db is on this command line, which "
                  "`ps` shows to every user of this host for as long as it runs: set "
                  "$SLOPETUI_DB or use a ~/.pgpass file instead (the pools slopetui starts get "
                  "the URL in their environment)", file=sys.stderr)
    if args.command is None:  # the application
        from slopetui.tui.app import run_app
        return run_app(args.tui_db, start_workers=not args.no_workers)
    try:
        return int(args.handler(args))
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # `slopetui ... | head`: the reader left, nothing is wrong
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    except DatabaseFailure as exc:  # the disk is full, the file damaged, the server gone
        print(f"slopetui {args.command}: database error: {exc}", file=sys.stderr)
        return 1
    except Exception as exc:
        if isinstance(exc, loaded(USER_ERRORS)):
            print(f"slopetui {args.command}: error: {exc}", file=sys.stderr)
            return 2
        raise
