"""The arguments of ``slopetui continue``."""

from __future__ import annotations

import argparse

from slopetui.cli.arguments.orbit import add_point_options
from slopetui.sweeps.continuation_request import CONTINUABLE, MAX_STEP

#: The largest --from-hopf N. k_N grows like N^2 (omega_N ~ 2 pi N / tau): measured with
#: core.stability.hopf_k, at tau = 10 the 10th pair crosses at k = 24.4 (the top of the
#: paper's range), the 50th at k = 490; at tau = 2 the 50th at k = 12101.
MAX_HOPF_BRANCH = 50


def declare(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("continue", help="continue periodic orbits in one parameter: folds, "
                                        "period doublings, tori",
                       description="Pseudo-arclength continuation of a family of periodic "
                                   "orbits, from the Hopf point (--from-hopf), from a stored "
                                   "run's parameters (--from-run ID) or from the orbit a "
                                   "simulation at the given point settles on (default).")
    add_point_options(p)
    p.add_argument("--param", required=True, choices=CONTINUABLE,
                   help="the parameter to continue in")
    start = p.add_mutually_exclusive_group()
    start.add_argument("--from-hopf", dest="from_hopf", nargs="?", const="1", metavar="N",
                       help="start at the N-th Hopf point of the steady state in --param "
                            "(the N-th pair of roots crossing; default 1, the first; N > 1 "
                            "in k, tau, a, b or c)")
    start.add_argument("--from-run", dest="from_run", metavar="ID",
                       help="start from the orbit at a stored run's parameters")
    start.add_argument("--from-fold", dest="from_fold", nargs="?", const="1", metavar="N",
                       help="with --param2: the fold of cycles of the branch in --param born "
                            "at the N-th Hopf point (default 1), continued as a curve in "
                            "(--param, --param2)")
    start.add_argument("--from-pd", dest="from_pd", nargs="?", const="1", metavar="N",
                       help="with --param2: the first period doubling on the branch in "
                            "--param from the N-th Hopf point (default 1), followed up to --to "
                            "(real: the multiplier through -1 beyond its uncertainty), "
                            "continued as a curve in (--param, --param2)")
    start.add_argument("--from-ns", dest="from_ns", nargs="?", const="1", metavar="N",
                       help="with --param2: the first torus (Neimark-Sacker) bifurcation on "
                            "the branch in --param from the N-th Hopf point (default 1), "
                            "followed up to --to (real: a complex pair through the circle "
                            "beyond its uncertainty), continued as a curve in (--param, "
                            "--param2), with the strong resonances along it")
    p.add_argument("--param2", choices=CONTINUABLE, metavar="Q",
                   help="a second parameter: continue a curve in (--param, Q) from "
                        "--from-fold (the fold of cycles, with its codimension-two points), "
                        "--from-hopf (the Hopf curve with its first Lyapunov coefficient l1 "
                        "and Bautin points), --from-pd or --from-ns; needs --to2")
    p.add_argument("--to2", metavar="VALUE",
                   help="with --param2: where the curve ends in Q")
    p.add_argument("--to", metavar="VALUE",
                   help="stop once the parameter passes VALUE (default: the Hopf point or "
                        "--points)")
    p.add_argument("--points", default="300", metavar="N",
                   help="at most N points (default 300, from 2 to 5000)")
    p.add_argument("--max-step", dest="max_step", default="0.5", metavar="X",
                   help=f"largest step along the branch (default 0.5, at most {MAX_STEP:g})")
    p.add_argument("--switch-pd", dest="switch_pd", action="store_true",
                   help="at the branch's first period doubling, switch onto the branch of "
                        "orbits of twice the period born there and follow it too (the same "
                        "--points and --to); computed here, not with --submit")
    p.add_argument("--submit", action="store_true",
                   help="queue the continuation for the workers (`slopetui worker`, the "
                        "application's pool) instead of computing it here; it is stored point "
                        "by point, resumes where it stopped, and `slopetui branch ID` shows it")
    p.add_argument("--db", metavar="URL",
                   help="the store of --from-run and --submit (default as for run)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
