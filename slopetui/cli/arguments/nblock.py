"""The arguments of ``slopetui nblock``."""

from __future__ import annotations

import argparse

from core.params import PARAM_NAMES
from slopetui.cli.arguments.run import PARAM_HELP


def declare(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "nblock", help="compare the N-block model (eq. 5) with the mean field",
        description="Integrate the original stochastic N-block model (eq. 5, Euler-Maruyama) "
                    "and the mean-field equations (6a-6e, Euler) on the same parameters, print "
                    "how far apart their moments are for each N and d, say where the Gaussian "
                    "closure holds, and plot both side by side.")
    for name in PARAM_NAMES:
        if name != "d":
            p.add_argument(f"--{name}", dest=name, metavar="X", help=PARAM_HELP[name])
    p.add_argument("--n", default="10,100,1000", metavar="N,N,..",
                   help="ensemble sizes (default 10,100,1000)")
    p.add_argument("--d", default="1e-4,1e-2,1e-1", metavar="D,D,..",
                   help="noise intensities (default 1e-4,1e-2,1e-1)")
    p.add_argument("--t-end", dest="t_end", type=float, default=50.0, metavar="T",
                   help="end time (default 50: about five periods at tau = 10, k = 10)")
    p.add_argument("--dt", type=float, default=1e-3, metavar="X", help="time step (default 1e-3)")
    p.add_argument("--seed", default="0", help="random seed, an integer >= 0 (default 0)")
    p.add_argument("--no-plot", dest="plot", action="store_false",
                   help="only the table (the plot shows the largest N at the smallest d)")
    p.add_argument("--color", choices=("auto", "always", "never"), default="auto")
