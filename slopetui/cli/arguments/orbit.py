"""The arguments of ``slopetui orbit``."""

from __future__ import annotations

import argparse

from core.params import PARAM_NAMES
from slopetui.cli.arguments.run import PARAM_HELP, accept_negative_numbers
from slopetui.sweeps.orbit_point import MAX_SEED_STEPS, MIN_T_SEED

#: The most slips a period --slips asks for: at k = 18, tau = 10 the 6-slip orbit's period
#: is 1.73, near the slip's own duration; more slips than this no longer fit a basic period.
MAX_SLIPS = 20


def add_point_options(p: argparse.ArgumentParser) -> None:
    """The parameter flags of ``run`` (--k, --tau, ...) and the orbit's step."""
    accept_negative_numbers(p)
    for name in PARAM_NAMES:
        p.add_argument(f"--{name}", dest=name, metavar="X", help=PARAM_HELP[name])
    p.add_argument("--dt", metavar="X", default="0.01",
                   help="RK4 step of the orbit (default 0.01; tau = N dt exactly)")


def declare(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("orbit", help="the periodic orbit at one point, with its Floquet multipliers",
                       description="Simulate from eq. 19 (offset --delta), find where the state "
                                   "returns, and correct the orbit by Newton-Krylov shooting; "
                                   "print its period, amplitude, maxima per period, leading "
                                   "Floquet multipliers and stability.")
    add_point_options(p)
    p.add_argument("--t-seed", dest="t_seed", metavar="X", default="3000",
                   help=f"length of the seed simulation, from {MIN_T_SEED:g} to "
                        f"{MAX_SEED_STEPS:g} steps of --dt (default 3000)")
    p.add_argument("--slips", metavar="N",
                   help=f"the equally spaced N-slip orbit (N from 1 to {MAX_SLIPS}), period "
                        "T / N where T is the seed simulation's return: its slip cycle "
                        "stretched to T / N and repeated over the delay (default: the orbit "
                        "the simulation settles on; several unequal slips a return seek the "
                        "equally spaced orbit they tend to)")
    p.add_argument("--from-run", dest="from_run", metavar="ID",
                   help="seed from stored run ID's final state instead of eq. 19 (its "
                        "parameters, unless given; its tau)")
    p.add_argument("--db", metavar="URL", help="the store of --from-run (default as for run)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
