"""What each ``slopetui`` command accepts: its arguments, their help and their ranges.

One module per command (a command's handler lives in ``slopetui.cli.<command>``). These
modules are light on purpose: ``slopetui --help`` and shell completion build the whole
parser from them, so they import argparse and the names a parser shows (from homes
without numpy, numba or SQLAlchemy: ``core.params``, ``core.methods``,
``slopetui.sweeps.sizes``...), never a handler's module. A range that the help states and
the handler checks is defined here, and the handler imports it.
"""
