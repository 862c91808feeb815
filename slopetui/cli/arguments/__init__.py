"""What each ``slopetui`` command accepts: its arguments, their help and their ranges.

One module per command (a command's handler lives in ``slopetui.cli.<command>``). These
modules are light on purpose: ``slopetui --help`` and shell completion build the whole
parser from them, so they import argparse and the names a parser shows (from homes
without numpy, numba or SQLAlchemy: ``core.params``, ``core.methods``,
``slopetui.sweeps.sizes``...), never a handler's module. A range that the help states and
the handler checks is defined here, and the handler imports it.
"""

from __future__ import annotations

import argparse

from slopetui.store.location import DB_ENV


def add_db_option(parser: argparse.ArgumentParser) -> None:
    """The ``--db URL`` option of the commands that open the store."""
    parser.add_argument("--db", metavar="URL",
                        help=f"SQLAlchemy database URL (default: ${DB_ENV}, else SQLite in "
                             "the user data folder, ~/.local/share/slopetui/slopetui.db)")
