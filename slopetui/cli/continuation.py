"""``slopetui continue``: follow a family of periodic orbits in one parameter and locate
its folds, period doublings and tori (and, from the Hopf point, its criticality)."""

from __future__ import annotations

import argparse
import sys
import time
from typing import TYPE_CHECKING

from core.branch_start import MIN_STEP, past_end, start
from core.branch_switch import half_shift, period_doubled
from core.continuation import bifurcations, criticality, walk
from core.lyapunov_coefficient import first_lyapunov
from core.orbit import OrbitError
from core.params import PARAM_NAMES, ParameterError, Params
from slopetui.cli.arguments.continuation import MAX_HOPF_BRANCH
from slopetui.cli.branch_lines import print_bifurcations, print_point
from slopetui.cli.curve import run_curve
from slopetui.cli.options import int_arg, open_db, say_queued
from slopetui.cli.orbit import point_of
from slopetui.json_text import json_text
from slopetui.provenance import computed_at
from slopetui.queue.warm_up import say_if_compiling
from slopetui.store.queries import run_by_id
from slopetui.sweeps.branch_records import bifurcation_record, point_record
from slopetui.sweeps.branches import submit
from slopetui.sweeps.continuation_request import continuation_spec
from slopetui.sweeps.curve_request import curve_spec
from slopetui.sweeps.curves import submit as submit_curve

if TYPE_CHECKING:
    from core.branch_start import BranchSpec
    from core.continuation import Bifurcation, Branch, BranchPoint


def _check(args: argparse.Namespace) -> None:
    """--from-hopf, --from-run, --from-fold, --from-pd and --from-ns as numbers (one line
    naming a bad one; the rest are continuation_spec's and curve_spec's)."""
    if args.from_hopf is not None:
        args.from_hopf = int_arg("from-hopf", args.from_hopf, 1, MAX_HOPF_BRANCH,
                                 note=" (the Hopf branch: 1 the first root crossing)")
    if args.from_run is not None:
        args.from_run = int_arg("from-run", args.from_run, 1, note=" (a run id)")
    for flag, what in (("fold", "fold"), ("pd", "period doubling"), ("ns", "torus")):
        if getattr(args, f"from_{flag}") is not None:
            setattr(args, f"from_{flag}", int_arg(
                f"from-{flag}", getattr(args, f"from_{flag}"), 1, MAX_HOPF_BRANCH,
                note=f" (the Hopf branch whose {what} starts the curve)"))


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
    return bifurcation_record(b.type, b.value, b.period, b.multiplier, b.reason)


def _submit(args: argparse.Namespace, spec: BranchSpec) -> int:
    cid = submit(open_db(args), spec, args.from_run)
    return say_queued(args.json, "continuation", cid, f"slopetui branch {cid}")


def _curve(args: argparse.Namespace, params: Params, dt: float) -> int:
    """A curve in two parameters (--param2), computed here or queued (--submit)."""
    chosen = [(s, getattr(args, f"from_{s}")) for s in ("fold", "hopf", "pd", "ns")
              if getattr(args, f"from_{s}") is not None]
    if not chosen:
        raise ParameterError("param2", args.param2, "given with --from-fold, --from-hopf, "
                             "--from-pd or --from-ns")
    start, hopf_branch = chosen[0]
    spec = curve_spec(params, dt, args.param, args.param2, start, args.to2, args.points,
                      args.max_step, hopf_branch, args.to)
    if args.submit:
        cid = submit_curve(open_db(args), spec)
        return say_queued(args.json, "curve", cid, f"slopetui curve {cid}")
    return run_curve(args, spec)


def handle(args: argparse.Namespace) -> int:
    try:
        params, dt = point_of(args)
        _check(args)
        if args.param2 is not None:
            return _curve(args, params, dt)
        if args.from_fold is not None or args.from_pd is not None or \
                args.from_ns is not None or args.to2 is not None:
            raise ParameterError("param2", "", "a second parameter: --from-fold, --from-pd, "
                                 "--from-ns and --to2 continue a curve in (--param, --param2)")
        if args.from_run is not None:
            params = _params_of_run(args, params)
        spec = continuation_spec(params, dt, args.param, args.from_hopf is not None, args.to,
                                 args.points, args.max_step, hopf_branch=args.from_hopf or 1)
    except ParameterError as exc:
        print(f"slopetui continue: error: {exc}", file=sys.stderr)
        return 2
    if args.submit:
        if args.switch_pd:
            print("slopetui continue: error: switch-pd is computed here, not with --submit",
                  file=sys.stderr)
            return 2
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
        out["hopf"] = {"value": hopf.value, "period": hopf.period, "branch": hopf.branch,
                       "omega": hopf.omega}
        ly = first_lyapunov(spec.params, args.param, spec.dt, hopf.branch)
        out["l1"] = ly.l1
        # the normal form decides; the branch's first orbits are the check (they differ
        # only where l1 is within its error of 0: next to a Bautin point)
        if ly.criticality != critical:
            out["criticality_note"] = (f"the branch's first orbits look {critical}; l1 = "
                                       f"{ly.l1:.3g} decides")
        critical = ly.criticality
        out["criticality"] = critical
    if args.switch_pd:
        out["doubled"] = _doubled(args, spec, branch, found)
    if quiet:
        print(json_text(out))
        return 0
    print(f"end: {branch.end} ({len(branch.points)} points, {took:.1f} s)")
    if hopf is not None:
        print(f"Hopf point {hopf.branch}: {args.param} = {hopf.value:.10g}, omega "
              f"{hopf.omega:.10g}, period {hopf.period:.10g}; {critical} (l1 = "
              f"{out['l1']:.6g})")
    print_bifurcations(args.param, bif_records)
    doubled = out.get("doubled")
    if isinstance(doubled, dict):
        print(f"period-doubled branch: {doubled['note']}")
        for point in doubled["branch"]:
            print_point(args.param, point)
        if doubled["branch"]:
            print(f"end: {doubled['end']}")
            print_bifurcations(args.param, doubled["bifurcations"])
    return 0


def _doubled(args: argparse.Namespace, spec: BranchSpec, branch: Branch,
             found: list[Bifurcation]) -> dict[str, object]:
    """The branch of period-2T orbits born at ``branch``'s first period doubling
    (core.branch_switch), walked as the branch was; each point with ``half_shift``, its
    distance from its own half-period shift (zero on the old orbit traversed twice)."""
    pd = next((b for b in found if b.type == "period-doubling"), None)
    if pd is None:
        return {"note": "no period doubling on this branch to switch at", "branch": [],
                "bifurcations": [], "end": ""}
    try:
        new = period_doubled(branch, pd)
    except OrbitError as exc:
        return {"note": f"no switch at {args.param} = {pd.value:.8g}: {exc}", "branch": [],
                "bifurcations": [], "end": ""}
    points = []
    for point in walk(new, lambda q: past_end(spec, pd.value, q), spec.max_points, MIN_STEP):
        record = _point_record(point)
        pm = new.map_at(point.value)
        record["half_shift"] = half_shift(pm, point.z, point.period)
        points.append(record)
    return {"note": f"switched at the period doubling {args.param} = {pd.value:.8g} "
                    f"(period {pd.period:.8g})", "at": _bif_record(pd), "branch": points,
            "bifurcations": [_bif_record(b) for b in bifurcations(new)], "end": new.end}
