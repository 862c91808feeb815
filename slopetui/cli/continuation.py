"""``slopetui continue``: follow a family of periodic orbits in one parameter and locate
its folds, period doublings and tori (and, from the Hopf point, its criticality)."""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from typing import TYPE_CHECKING

from core.params import PARAM_NAMES, ParameterError, Params
from slopetui.cli.orbit import add_point_options, point_of

if TYPE_CHECKING:
    from core.continuation import Bifurcation, Branch, BranchPoint
    from core.hopf_start import HopfPoint

#: Parameters a branch can follow: every parameter of the model but delta, which only
#: places the seed (eq. 19), not the orbit.
CONTINUABLE = tuple(n for n in PARAM_NAMES if n != "delta")


def register(sub: argparse._SubParsersAction) -> None:
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
    start.add_argument("--from-hopf", action="store_true",
                       help="start at the Hopf point of the steady state in --param")
    start.add_argument("--from-run", dest="from_run", metavar="ID", type=int,
                       help="start from the orbit at a stored run's parameters")
    p.add_argument("--to", metavar="VALUE",
                   help="stop once the parameter passes VALUE (default: the Hopf point or "
                        "--points)")
    p.add_argument("--points", type=int, default=300, metavar="N",
                   help="at most N points (default 300, from 2 to 5000)")
    p.add_argument("--max-step", dest="max_step", type=float, default=0.5, metavar="X",
                   help="largest step along the branch (default 0.5)")
    p.add_argument("--db", metavar="URL", help="the store of --from-run (default as for run)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(handler=handle)


def _end_value(args: argparse.Namespace, params: Params) -> float | None:
    """--to as a number inside the parameter's own range (Params names the range)."""
    if args.to is None:
        return None
    try:
        value = float(args.to)
    except ValueError:
        raise ParameterError("to", args.to, "a finite number") from None
    if not math.isfinite(value):
        raise ParameterError("to", args.to, "a finite number")
    params.with_(**{args.param: value})  # raises ParameterError naming the parameter
    return value


def _check(args: argparse.Namespace) -> None:
    if not 2 <= args.points <= 5000:
        raise ParameterError("points", args.points, "an integer from 2 to 5000")
    if not (math.isfinite(args.max_step) and args.max_step > 0):
        raise ParameterError("max-step", args.max_step, "a number > 0")


def _params_of_run(args: argparse.Namespace, params: Params) -> Params:
    """The stored run's parameters (flags given explicitly still win)."""
    from slopetui.store.open import open_store
    from slopetui.store.queries import run_by_id
    run = run_by_id(open_store(args.db), args.from_run)
    if run is None:
        raise ParameterError("from-run", args.from_run, "the id of a run in this store")
    given = {n for n in PARAM_NAMES if getattr(args, n) is not None}
    return params.with_(**{n: float(getattr(run, n)) for n in PARAM_NAMES if n not in given})


def start(args: argparse.Namespace, params: Params, dt: float, end: float | None
          ) -> tuple[Branch, HopfPoint | None]:
    """The branch's first point: from the Hopf point, or from a simulated orbit heading
    towards --to (down when --to is below the start, else up)."""
    from core.continuation import Branch
    from core.orbit import PeriodMap
    from core.periodic_orbit import find_orbit
    from core.shooting import Solution
    if args.from_hopf:
        return Branch.from_hopf(params, args.param, dt, 1e-3, 0.02, args.max_step)
    orbit = find_orbit(params, dt)
    shot = PeriodMap(params, orbit.grid).shoot(orbit.z, orbit.period)
    value = getattr(params, args.param)
    direction = -1.0 if end is not None and end < value else 1.0
    sol = Solution(orbit.z, orbit.period, shot, orbit.newton_steps, orbit.residual, 0)
    return Branch.from_orbit(params, orbit.grid, args.param, sol, direction,
                             0.05 * args.max_step, args.max_step), None


def _point_record(p: BranchPoint) -> dict[str, object]:
    lead = p.multipliers.leading
    return {"value": p.value, "period": p.period, "amplitude": p.amplitude, "stable": p.stable,
            "leading_multiplier": [lead.real, lead.imag]}


def _bif_record(b: Bifurcation) -> dict[str, object]:
    return {"type": b.type, "value": b.value, "period": b.period,
            "multiplier": [b.multiplier.real, b.multiplier.imag]}


def handle(args: argparse.Namespace) -> int:
    try:
        params, dt = point_of(args)
        end = _end_value(args, params)
        _check(args)
        if args.from_run is not None:
            params = _params_of_run(args, params)
    except ParameterError as exc:
        print(f"slopetui continue: error: {exc}", file=sys.stderr)
        return 2
    from core.continuation import bifurcations, criticality, walk
    from core.orbit import OrbitError
    t0 = time.process_time()
    try:
        branch, hopf = start(args, params, dt, end)
    except OrbitError as exc:
        print(f"slopetui continue: no branch: {exc}", file=sys.stderr)
        return 1

    def past_end(point: BranchPoint) -> bool:
        first = branch.points[0].value
        return end is not None and (point.value - end) * (end - first) >= 0

    quiet = args.json
    for point in walk(branch, past_end, args.points, 1e-7):
        if not quiet:
            print(f"{args.param} = {point.value:<12.8g} period {point.period:<12.8g} amplitude "
                  f"{point.amplitude:<10.6g} {'stable' if point.stable else 'unstable'}",
                  flush=True)
    found = bifurcations(branch)
    took = time.process_time() - t0
    out: dict[str, object] = {
        "param": args.param,
        "branch": [_point_record(p) for p in branch.points],
        "bifurcations": [_bif_record(b) for b in found],
        "end": branch.end,
        "dt": branch.g0.dt,
        "runtime_s": took,
    }
    critical = criticality(branch.points) if hopf is not None else None
    if hopf is not None:
        out["hopf"] = {"value": hopf.value, "period": hopf.period}
        out["criticality"] = critical
    if quiet:
        print(json.dumps(out))
        return 0
    print(f"end: {branch.end} ({len(branch.points)} points, {took:.1f} s)")
    if hopf is not None:
        print(f"Hopf point: {args.param} = {hopf.value:.10g}, period {hopf.period:.10g}; "
              f"{critical}")
    for b in found:
        print(f"{b.type:<16} {args.param} = {b.value:.8g}, period {b.period:.8g}"
              + (f", multiplier {b.multiplier.real:+.6f}{b.multiplier.imag:+.6f}i"
                 if b.type not in ("fold", "hopf") else ""))
    if not found:
        print("no bifurcation on this branch")
    return 0
