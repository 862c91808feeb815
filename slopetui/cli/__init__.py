# PYTHON_ARGCOMPLETE_OK
"""The ``slopetui`` command line, built from a table: each command's arguments are declared
by a light module of ``slopetui.cli.arguments`` (``--help`` and shell completion build the
whole parser from them), and its handler's module, which imports at its top whatever the
command needs (the store, numpy, numba's kernels), is imported only when that command runs.

A new command is a module of ``slopetui.cli.arguments`` with ``declare(sub)`` (named in
ARGUMENTS), and its handler, ``handle(args) -> exit status``, in a module of its own
(named in HANDLERS); tests/unit/test_cli.py checks that the two tables agree.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
from collections.abc import Callable, Sequence
from typing import cast

from slopetui import __version__
from slopetui.cli import completion
from slopetui.store.failures import DatabaseFailure, StoreError
from slopetui.store.location import checked_url
from slopetui.store.url_text import holds_password

#: The modules of slopetui.cli.arguments that declare the commands' arguments, in the
#: order ``slopetui --help`` lists the commands (imported by name: bound here, `run` or
#: `sql` would hide the handlers' modules of the same names).
ARGUMENTS = ("run", "orbit", "roots", "continuation", "branch", "curve", "hysteresis", "submit", "example",
             "rerun", "status", "show", "figure", "runs", "control", "delete", "sql", "worker",
             "workers", "db", "cluster", "nblock", "reproduce", "completion", "annotate",
             "compare")

#: Each command's handler, ``module:function``: the module is imported on dispatch only.
HANDLERS = {
    "run": "slopetui.cli.run:handle",
    "orbit": "slopetui.cli.orbit:handle",
    "roots": "slopetui.cli.roots:handle",
    "continue": "slopetui.cli.continuation:handle",
    "branch": "slopetui.cli.branch:handle",
    "curve": "slopetui.cli.curve_show:handle",
    "hysteresis": "slopetui.cli.hysteresis:handle",
    "submit": "slopetui.cli.submit:handle",
    "example": "slopetui.cli.example:handle",
    "rerun": "slopetui.cli.rerun:handle",
    "status": "slopetui.cli.status:handle",
    "show": "slopetui.cli.show:handle",
    "figure": "slopetui.cli.figure:handle",
    "runs": "slopetui.cli.runs:handle_runs",
    "export": "slopetui.cli.export:handle",
    "cancel": "slopetui.cli.control:handle",
    "pause": "slopetui.cli.control:handle",
    "resume": "slopetui.cli.control:handle",
    "delete": "slopetui.cli.delete:handle",
    "sql": "slopetui.cli.sql:handle",
    "worker": "slopetui.cli.worker:handle",
    "workers": "slopetui.cli.workers:handle",
    "db": "slopetui.cli.db:handle",
    "cluster": "slopetui.cli.cluster:handle",
    "nblock": "slopetui.cli.nblock:handle",
    "reproduce": "slopetui.cli.reproduce:handle",
    "completion": "slopetui.cli.completion:handle",
    "rename": "slopetui.cli.annotate:handle_rename",
    "note": "slopetui.cli.annotate:handle_note",
    "tag": "slopetui.cli.annotate:handle_tag",
    "sweeps": "slopetui.cli.annotate:handle_sweeps",
    "compare": "slopetui.cli.compare:handle",
}
#: Without a command: the terminal application, imported as a handler is.
APPLICATION = "slopetui.tui.app:run_app"

#: Errors that are the user's input or environment, not a bug: one line, no traceback,
#: exit 2. Named by module, and looked up in sys.modules once the handler has raised: the
#: handler's module imports at its top every module it uses, so a class whose module is
#: not loaded then cannot have been raised, and the check is exact. Importing the classes
#: here instead would give every command, `example` and `completion` included, the
#: imports of the heaviest: core.orbit loads numba (0.5 s), slopetui.sweeps.spec numpy
#: (0.15 s), slopetui.sweeps.control the store (0.3 s) (python -c "import M", this host).
USER_ERRORS = (("core.params", "ParameterError"), ("core.orbit", "OrbitError"),
               ("slopetui.sweeps.spec", "SpecError"), ("slopetui.store.failures", "StoreError"),
               ("slopetui.sweeps.control", "UnknownSweep"), ("slopetui.cli.options", "UsageError"),
               ("slopetui.sweeps.annotations", "LabelError"))
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
    for name in ARGUMENTS:
        importlib.import_module(f"slopetui.cli.arguments.{name}").declare(sub)
    return parser


def imported(target: str) -> Callable[..., int]:
    """The function named by ``target`` (``module:function``), its module imported now."""
    module, _, function = target.partition(":")
    return cast("Callable[..., int]", getattr(importlib.import_module(module), function))


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
    if args.command is None:
        return int(imported(APPLICATION)(args.tui_db, start_workers=not args.no_workers))
    try:
        return int(imported(HANDLERS[args.command])(args))
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
