"""The arguments of ``slopetui submit``."""

from __future__ import annotations

import argparse

from core.methods import METHODS
from core.params import PARAM_NAMES
from slopetui.cli.arguments import add_db_option
from slopetui.cli.arguments.run import PARAM_HELP, accept_negative_numbers
from slopetui.sweeps.sizes import CONFIRM_ABOVE_RUNS


def declare(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "submit", help="queue a 1-D or 2-D sweep",
        description="Queue a sweep: a TOML spec file (docs/sweeps.md), flags, or a file with "
                    "flags that override it. Axes take PARAM=START:STOP:NUM[:log].",
        epilog="examples: slopetui submit fig4a; "
               "slopetui submit --x k=3:24:43 --tau 10 --delta 0.1 --t-end 1e4")
    accept_negative_numbers(p)
    p.add_argument("spec", nargs="?", metavar="SPEC.toml",
                   help="a TOML sweep spec file; or, when no such file exists, the name of a "
                        "shipped example (`slopetui example` lists them, e.g. fig4a)")
    p.add_argument("--x", metavar="AXIS", help="x axis, e.g. k=3:24:43 or tau=0.1:60:40:log")
    p.add_argument("--y", metavar="AXIS", help="y axis (makes a phase diagram)")
    for name in PARAM_NAMES:
        p.add_argument(f"--{name}", dest=f"fixed_{name}", metavar="X",
                       help=f"fixed {PARAM_HELP[name]}")
    p.add_argument("--name", help="a name for the sweep (at most 200 characters; control "
                                  "characters such as ESC or bidi overrides are refused)")
    p.add_argument("--method", choices=METHODS, help="euler (default), rk4 or stiff")
    p.add_argument("--dt", metavar="X", help="time step (default 1e-3 euler, 1e-2 rk4)")
    p.add_argument("--t-end", dest="t_end", metavar="X", help="end time (default 1e5)")
    p.add_argument("--window", metavar="X",
                   help="analysis window (default min(1000, t_end / 2))")
    p.add_argument("--no-lyap", dest="lyap", action="store_false", default=None,
                   help="skip lambda_max (about 1.5x faster with Euler)")
    p.add_argument("--history", metavar="H",
                   help="m_x before t = 0 for every run: constant (default, eq. 19) or "
                        "consistent (delta (1 + t), no kink at t = 0)")
    p.add_argument("--stop", metavar="RULE",
                   help="when each run stops: certified (default for a spec that does not "
                        "say: as soon as its attractor is certified from its own state, a "
                        "fixed point by its root and decay, an orbit by its multipliers, else "
                        "at t_end; far cheaper where runs settle early) or t_end (the paper's "
                        "protocol, which the shipped examples and presets keep)")
    p.add_argument("--initial", action="append", metavar="COND",
                   help="compute every point from this initial condition too (repeat it): "
                        "delta=X and/or history=H (constant, consistent, run:ID: a stored "
                        "run's final state), e.g. --initial delta=1e-6 --initial delta=0.1; "
                        "the phase diagram then shows where they end in different regimes")
    p.add_argument("--adaptive", metavar="LEVELS",
                   help="a 2-D sweep as an adaptive phase diagram: compute a lattice "
                        "2**LEVELS times coarser, refine only where regimes change, infer "
                        "the rest (LEVELS 1..8; the axes give the final lattice)")
    p.add_argument("--yes", action="store_true",
                   help=f"queue sweeps of more than {CONFIRM_ABOVE_RUNS} runs (adaptive: "
                        "coarse runs)")
    p.add_argument("--json", action="store_true",
                   help="print {sweep_id, n_runs, n_cached} (adaptive: also n_points, "
                        "adaptive_levels)")
    add_db_option(p)
