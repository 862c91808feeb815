"""Shell completion with argcomplete: ``enable(parser)``, which answers a shell's <TAB>,
and ``slopetui completion SHELL``, which prints the code a shell sources to ask.

The shell runs ``slopetui`` with ``_ARGCOMPLETE`` and the command line in its
environment; ``main()`` then calls ``enable`` instead of running a command. argcomplete is
imported there only (~15 ms): a normal command and ``--help`` never load it.

Subcommands, options and ``choices`` complete by themselves. Ids complete by metavar, so
that a command added later gets them by naming its arguments after the convention:

- metavar ``SWEEP`` (positional or option): sweep ids, newest first, with the sweep's
  name as the description zsh and fish show;
- metavar ``RUN``: run ids, the newest ``RUN_LIMIT`` whose id starts with what is typed,
  described by their sweep and regime. Options that take a run id under another
  metavar are named in ``RUN_OPTIONS`` (``continue --from-run ID``, whose ``ID`` is
  also the metavar of continuation and hysteresis ids).

The ids are read (``slopetui.store.id_lists``) from the store named by the command's
``--db`` if it is already on the line, else ``$SLOPETUI_DB``, else the default file.
Completion never creates or migrates a store, and never shows an error in the user's
shell: a missing store, a damaged one, a server that does not answer all complete to
nothing.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import sys
import warnings
from collections.abc import Callable, Iterator

from slopetui.display_text import terminal_safe
from slopetui.store.id_lists import newest_run_ids, sweep_ids
from slopetui.store.location import default_url

#: Options that take a run id but predate the RUN metavar convention.
RUN_OPTIONS = frozenset({"--from-run"})
#: The longest sweep name shown as a description (a menu line, not the whole name).
NAME_WIDTH = 60


def handle(args: argparse.Namespace) -> int:
    from argcomplete import shellcode

    sys.stdout.write(shellcode(["slopetui"], shell=args.shell))
    return 0


def enable(parser: argparse.ArgumentParser) -> None:
    """Attach the id completers to ``parser`` and its subparsers, then answer the shell
    (argcomplete writes the completions and ends the process)."""
    try:
        import argcomplete
    except ImportError:  # a broken install: complete nothing rather than run a command
        raise SystemExit(1) from None
    attach(parser)
    argcomplete.autocomplete(parser)


def attach(parser: argparse.ArgumentParser) -> None:
    """Set the completer of every SWEEP and RUN argument of ``parser``, subparsers
    included (see the module docstring)."""
    for action in walk(parser):
        if action.metavar == "SWEEP":
            action.completer = complete_sweeps  # type: ignore[attr-defined]
        elif action.metavar == "RUN" or RUN_OPTIONS.intersection(action.option_strings):
            action.completer = complete_runs  # type: ignore[attr-defined]


def walk(parser: argparse.ArgumentParser) -> Iterator[argparse.Action]:
    """The actions of ``parser`` and of its subparsers, recursively."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for subparser in dict.fromkeys(action.choices.values()):  # aliases: once each
                yield from walk(subparser)
        else:
            yield action


def complete_sweeps(prefix: str, parsed_args: argparse.Namespace, **_: object) -> dict[str, str]:
    """Sweep id -> the sweep's name."""
    def read(url: str) -> dict[str, str]:
        return {str(i): shorten(name) for i, name in sweep_ids(url, prefix)}

    return quietly(read, parsed_args)


def complete_runs(prefix: str, parsed_args: argparse.Namespace, **_: object) -> dict[str, str]:
    """Run id -> "sweep N, regime" (or its status while it has no regime)."""
    def read(url: str) -> dict[str, str]:
        return {str(i): shorten(f"sweep {sweep}, {regime or status}")
                for i, sweep, regime, status in newest_run_ids(url, prefix)}

    return quietly(read, parsed_args)


def quietly(read: Callable[[str], dict[str, str]], parsed_args: argparse.Namespace) -> dict[str, str]:
    """``read(url)`` of the store the command would use, or nothing if anything fails:
    whatever goes wrong, the user's shell must not see a traceback or a warning."""
    try:
        with warnings.catch_warnings(), contextlib.redirect_stderr(io.StringIO()):
            warnings.simplefilter("ignore")
            return read(store_url(parsed_args))
    except Exception:
        return {}


def store_url(parsed_args: argparse.Namespace) -> str:
    """The store the command being completed would open: its --db, else the default."""
    return getattr(parsed_args, "db", None) or default_url()


def shorten(text: str) -> str:
    """Stored text as one safe menu line: control characters escaped (a stored escape
    sequence must not drive the terminal, a newline or tab would break the shell's list),
    at most NAME_WIDTH characters."""
    safe = terminal_safe(text)
    return safe if len(safe) <= NAME_WIDTH else safe[:NAME_WIDTH - 3] + "..."

