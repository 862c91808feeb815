"""The arguments of ``slopetui orbit``."""

from __future__ import annotations

import argparse

from core.params import PARAM_NAMES
from slopetui.cli.arguments.run import PARAM_HELP, accept_negative_numbers
from slopetui.sweeps.orbit_point import MAX_SEED_STEPS, MIN_T_SEED


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
    p.add_argument("--json", action="store_true", help="print one JSON object")
