"""The arguments of ``slopetui roots``."""

from __future__ import annotations

import argparse

from core.params import PARAM_NAMES
from slopetui.cli.arguments.run import PARAM_HELP, accept_negative_numbers

#: The most roots asked for: h has infinitely many, spaced ~2 pi / tau apart along the
#: imaginary axis; the collocation (core.stability) resolves the rightmost few dozen.
MAX_COUNT = 40


def declare(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("roots", help="the rest state's characteristic roots at one point",
                       description="The rightmost roots of the characteristic function of the "
                                   "rest state (the sliding state of eq. 18, with its noise d), "
                                   "the m_x shift's zero root left out: the delay factor h of "
                                   "eq. 20 by Chebyshev collocation refined by Newton, and the "
                                   "variance block's, each carried to the noisy state when "
                                   "d > 0. The leading root's sign is the rest state's linear "
                                   "stability.")
    accept_negative_numbers(p)
    for name in PARAM_NAMES:
        p.add_argument(f"--{name}", dest=name, metavar="X", help=PARAM_HELP[name])
    p.add_argument("--count", metavar="N", default="6",
                   help=f"how many roots of h (1 to {MAX_COUNT}; default 6), and the "
                        "variance block's (Im >= 0: two of its three)")
    out = p.add_mutually_exclusive_group()
    out.add_argument("--plot", action="store_true",
                     help="draw the roots in the complex plane (Re against Im)")
    out.add_argument("--json", action="store_true", help="print one JSON object")
