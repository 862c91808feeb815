"""The arguments of ``slopetui run``."""

from __future__ import annotations

import argparse
import re

from core.methods import METHODS
from core.params import PARAM_NAMES

PARAM_HELP = {
    "a": "friction coefficient a (default 3.2)",
    "b": "friction coefficient b (default 7.2)",
    "c": "friction coefficient c (default 4.8)",
    "d": "noise intensity d >= 0 (default 1e-4)",
    "k": "spring stiffness k >= 0 (default 10)",
    "v": "steady sliding velocity v (default 0.1)",
    "tau": "delay tau >= 0 (default 10)",
    "delta": "initial offset delta of eq. 19 (default 0.1)",
}

#: A negative number as scientific notation ("-1e-3", "-2.5E4") or -inf/-nan. argparse
#: (Python 3.11, 3.12) only knows "-3" and "-0.5": it took "--a -1e-3" for an option
#: and stopped with "expected one argument", though the model has negative a, v, delta.
NEGATIVE_NUMBER = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$|^-(inf|infinity|nan)$",
                             re.IGNORECASE)

def accept_negative_numbers(parser: argparse.ArgumentParser) -> None:
    """Let option values be negative numbers in any notation (see NEGATIVE_NUMBER). The
    matcher is argparse's private attribute, unchanged since Python 3.2; the parser has
    no option that looks like a negative number, so nothing else is affected."""
    parser._negative_number_matcher = NEGATIVE_NUMBER


def declare(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("run", help="run one parameter point and print its regime",
                       description="Integrate eqs. 6a-6e at one point, classify the analysis "
                                   "window and estimate lambda_max.")
    accept_negative_numbers(p)
    for name in PARAM_NAMES:
        p.add_argument(f"--{name.replace('_', '-')}", dest=name, metavar="X", help=PARAM_HELP[name])
    p.add_argument("--method", choices=METHODS, default="euler",
                   help="euler (paper-faithful, default), rk4 (4th order) or stiff (linearly "
                        "implicit: what euler and rk4 fall back to where they fail)")
    p.add_argument("--dt", metavar="X", help="time step (default 1e-3 for euler, 1e-2 for rk4)")
    p.add_argument("--t-end", dest="t_end", metavar="X", default="1e5",
                   help="end time of the run (default 1e5)")
    p.add_argument("--window", metavar="X",
                   help="analysis window at the end of the run (default min(1000, t_end / 2): "
                        "the paper's 1000, or half of a shorter run)")
    p.add_argument("--no-lyap", dest="lyap", action="store_false", help="skip lambda_max")
    p.add_argument("--spectrum", metavar="N", default="0",
                   help="also the top N Lyapunov exponents with their errors, the m_x shift "
                        "quotiented out (1 <= N <= 16; euler or rk4): the evidence for a torus "
                        "or chaos (a second pass of the scheme, about N tangents' work)")
    p.add_argument("--history", default="constant", metavar="H",
                   help="m_x before t = 0: constant (default, m_x = delta: eq. 19 as the paper "
                        "reads), consistent (m_x = delta (1 + t): no kink at t = 0), or run:ID "
                        "(the final state of a stored run with the same tau and step, "
                        "recomputed)")
    p.add_argument("--stop", default="t_end", metavar="RULE",
                   help="when the run stops: t_end (default: the paper's protocol, the whole "
                        "run to t_end) or certified (as soon as its attractor is certified "
                        "from its own state: a fixed point by its root and decay, an orbit by "
                        "its multipliers; else at t_end too)")
    p.add_argument("--db", metavar="URL", help="the store of --history run:ID (default as "
                                               "for submit)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
