"""``slopetui continue``: follow a family of periodic orbits in one parameter and locate
its folds, period doublings and tori (and, from the Hopf point, its criticality)."""

from __future__ import annotations

import argparse
import math
import sys
import time
from typing import TYPE_CHECKING

from core.branch_start import MIN_STEP, BranchSpec, past_end, start
from core.continuation import bifurcations, criticality, walk
from core.orbit import OrbitError
from core.params import PARAM_NAMES, ParameterError, Params
from core.periodic_orbit import SEED_T_END
from slopetui.cli.arguments.continuation import MAX_STEP
from slopetui.cli.branch_lines import print_bifurcations, print_point
from slopetui.cli.options import float_arg, int_arg, open_db, say_queued
from slopetui.cli.orbit import check_seed_steps, point_of
from slopetui.json_text import json_text
from slopetui.provenance import computed_at
from slopetui.queue.warm_up import say_if_compiling
from slopetui.store.queries import run_by_id
from slopetui.sweeps.branch_records import bifurcation_record, point_record
from slopetui.sweeps.branches import submit

if TYPE_CHECKING:
    from core.branch_start import BranchSpec
    from core.continuation import Bifurcation, BranchPoint


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


def _not_the_start(args: argparse.Namespace, params: Params, end: float | None) -> None:
    """--to other than where the branch starts (the simulated orbit's or the stored run's
    parameter; the Hopf point is not known yet): before, a branch from there to there
    took one step past it and exited 0."""
    here = getattr(params, args.param)
    if end is not None and not args.from_hopf and end == here:
        raise ParameterError("to", args.to, f"a value other than the start, {args.param} = {here:g}")


def _check(args: argparse.Namespace) -> None:
    """--points, --max-step and --from-run as numbers (one line naming a bad one)."""
    args.points = int_arg("points", args.points, 2, 5000)
    args.max_step = float_arg("max-step", args.max_step, 0, MAX_STEP, above=True)
    if args.from_run is not None:
        args.from_run = int_arg("from-run", args.from_run, 1, note=" (a run id)")


def _params_of_run(args: argparse.Namespace, params: Params) -> Params:
    """The stored run's parameters (flags given explicitly still win)."""
    run = run_by_id(open_db(args), args.from_run)
    if run is None:
        raise ParameterError("from-run", args.from_run, "the id of a run in this store")
    given = {n for n in PARAM_NAMES if getattr(args, n) is not None}
    return params.with_(**{n: float(getattr(run, n)) for n in PARAM_NAMES if n not in given})


def _point_record(p: BranchPoint) -> dict[str, object]:
    return point_record(p.value, p.period, p.amplitude, p.stable, p.multipliers.leading)


def _bif_record(b: Bifurcation) -> dict[str, object]:
    return bifurcation_record(b.type, b.value, b.period, b.multiplier)


def _submit(args: argparse.Namespace, spec: BranchSpec) -> int:
    cid = submit(open_db(args), spec, args.from_run)
    return say_queued(args.json, "continuation", cid, f"slopetui branch {cid}")


def handle(args: argparse.Namespace) -> int:
    try:
        params, dt = point_of(args)
        end = _end_value(args, params)
        _check(args)
        if args.from_run is not None:
            params = _params_of_run(args, params)
        _not_the_start(args, params, end)
        if not args.from_hopf:  # a simulated orbit's seed, held in memory
            check_seed_steps(params, dt, SEED_T_END)
    except ParameterError as exc:
        print(f"slopetui continue: error: {exc}", file=sys.stderr)
        return 2
    spec = BranchSpec(params, args.param, dt, args.from_hopf, end, args.points, args.max_step)
    if args.submit:
        return _submit(args, spec)
    say_if_compiling("continue")
    t0 = time.process_time()
    try:
        branch, hopf = start(spec)
    except OrbitError as exc:
        print(f"slopetui continue: no branch: {exc}", file=sys.stderr)
        return 1

    quiet = args.json
    for point in walk(branch, lambda q: past_end(spec, branch.points[0].value, q), spec.max_points,
                      MIN_STEP):
        if not quiet:
            print_point(args.param, _point_record(point))
    found = bifurcations(branch)
    bif_records = [_bif_record(b) for b in found]
    took = time.process_time() - t0
    out: dict[str, object] = {
        "param": args.param,
        "branch": [_point_record(p) for p in branch.points],
        "bifurcations": bif_records,
        "end": branch.end,
        "dt": branch.g0.dt,
        "runtime_s": took,
        # the branch's start (``param`` varies along it: at the Hopf point, or the first
        # point's value); RK4 is the orbits' map (core.period_map); points and max_step: how
        # far and in what steps it was followed
        **computed_at(params, {"method": "rk4", "dt": branch.g0.dt, "from_hopf": spec.from_hopf,
                               "points": spec.max_points, "max_step": spec.max_step},
                      start=(args.param, hopf.value if hopf is not None
                             else branch.points[0].value if branch.points else None)),
    }
    critical = criticality(branch.points) if hopf is not None else None
    if hopf is not None:
        out["hopf"] = {"value": hopf.value, "period": hopf.period}
        out["criticality"] = critical
    if quiet:
        print(json_text(out))
        return 0
    print(f"end: {branch.end} ({len(branch.points)} points, {took:.1f} s)")
    if hopf is not None:
        print(f"Hopf point: {args.param} = {hopf.value:.10g}, period {hopf.period:.10g}; "
              f"{critical}")
    print_bifurcations(args.param, bif_records)
    return 0
