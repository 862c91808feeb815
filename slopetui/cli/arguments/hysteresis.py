"""The arguments of ``slopetui hysteresis``."""

from __future__ import annotations

import argparse

from core.params import PARAM_NAMES
from slopetui.cli.arguments import add_db_option
from slopetui.cli.arguments.orbit import add_point_options

#: Parameters a warm-started sweep can follow: not tau (the state's history is one delay
#: long and would change size) nor delta (which only places the first point's start).
FOLLOWABLE = tuple(n for n in PARAM_NAMES if n not in ("tau", "delta"))


def declare(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("hysteresis", help="warm-started sweep up and down one parameter: "
                                          "where the outcome depends on the path",
                       description="Along --param from --from to --to and back, each point "
                                   "starts from the final state of the previous one (the five "
                                   "variables and m_x, m_y over the last delay), so each branch "
                                   "follows its attractor until it disappears. A rest state "
                                   "whose perturbations grow (measured along the simulation) is "
                                   "kicked off. Prints both branches and where each changes "
                                   "regime; the first point starts from eq. 19 (--delta). "
                                   "--submit queues the sweep for the workers instead; "
                                   "--show ID prints a stored one.")
    add_point_options(p)
    # Not required=True: --show ID needs none of them (handle() names the missing one).
    p.add_argument("--param", choices=FOLLOWABLE, help="the parameter to follow")
    p.add_argument("--from", dest="start", metavar="X", help="first value")
    p.add_argument("--to", dest="stop", metavar="X", help="last value")
    p.add_argument("--points", default="40", metavar="N",
                   help="values from --from to --to, ends included (default 40, 2 to 2000)")
    p.add_argument("--t-settle", dest="t_settle", default=None, metavar="T",
                   help="time integrated at each point (default 6000)")
    p.add_argument("--window", default=None, metavar="T",
                   help="analysis window at the end of each point (default 1000)")
    p.add_argument("--tol", default=None, metavar="R",
                   help="each branch's transition is refined by bisection inside its grid "
                        "bracket to this tolerance, relative (default 1e-3; above 0, below "
                        "0.5; ~10 more settle runs at the default)")
    p.add_argument("--submit", action="store_true",
                   help="queue the sweep for the workers (`slopetui worker`, the application's "
                        "pool) instead of computing it here; it is stored point by point, "
                        "resumes where it stopped, and --show ID prints it")
    p.add_argument("--show", default=None, metavar="ID",
                   help="print the stored sweep ID (queued with --submit) as this command "
                        "prints a sweep it computes, with its status")
    p.add_argument("--plot", action="store_true", help="also draw both branches")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    add_db_option(p)
