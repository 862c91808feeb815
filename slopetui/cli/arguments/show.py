"""The arguments of ``slopetui show``."""

from __future__ import annotations

import argparse

from slopetui.cli.arguments import add_db_option

#: The smallest diagram that still has room for its axes, ticks and legend.
MIN_WIDTH, MIN_HEIGHT = 30, 12

#: The largest: plotext lays out every cell (a million here, 1.5 s more than 100 x 30), and no
#: terminal is wider or taller.
MAX_SIZE = 1000


def declare(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("show", help="draw a sweep's phase or bifurcation diagram",
                       description="Draw the sweep's phase diagram (2-D) or bifurcation "
                                   "diagram (1-D) in the terminal.")
    p.add_argument("sweep", metavar="SWEEP", nargs="?",
                   help="sweep id (default: the newest sweep)")
    p.add_argument("--width", metavar="N",
                   help=f"columns, {MIN_WIDTH} to {MAX_SIZE} (default: the terminal's)")
    p.add_argument("--height", metavar="N",
                   help=f"lines, {MIN_HEIGHT} to {MAX_SIZE} (default: the terminal's, at most "
                        "40)")
    p.add_argument("--color", choices=("auto", "always", "never"), default="auto",
                   help="auto: colour on a terminal unless NO_COLOR is set")
    p.add_argument("--no-hopf", dest="hopf", action="store_false",
                   help="do not draw the exact Hopf curve")
    p.add_argument("--fold", action="store_true",
                   help="also draw the fold of cycles over a (k, tau), (a, tau), (b, tau) or "
                        "(c, tau) plane, computed by "
                        "continuation at each tau of the sweep (about a second a tau up to "
                        "tau = 20, minutes at 60)")
    add_db_option(p)
