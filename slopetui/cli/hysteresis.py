"""``slopetui hysteresis``: follow the attractor along one parameter, up and then down,
each point warm-started from the final state of the one before (core.hysteresis); or
queue such a sweep for the workers (``--submit``) and read a stored one back (``--show``)."""

from __future__ import annotations

import argparse
import math
import shutil
import sys
import time
from collections.abc import Mapping, Sequence
from dataclasses import asdict
from typing import TYPE_CHECKING, Any

from core.params import ParameterError
from slopetui.cli.options import UsageError, int_arg, open_db, say_queued
from slopetui.display_text import terminal_safe
from slopetui.json_text import json_text
from slopetui.plots.hysteresis_plot import render_hysteresis
from slopetui.provenance import computed_at, params_of
from slopetui.queue.hysteresis_jobs import transition_fields
from slopetui.queue.warm_up import say_if_compiling
from slopetui.sweeps.hysteresis_request import hysteresis_spec
from slopetui.sweeps.hysteresis_runs import HysteresisSpec, hysteresis_of, submit

if TYPE_CHECKING:
    from core.hysteresis import WarmPoint
    from slopetui.sweeps.hysteresis_runs import StoredHysteresis

def _checked(args: argparse.Namespace) -> HysteresisSpec:
    from slopetui.cli.orbit import point_of  # numba: see _compute_or_submit

    params, dt = point_of(args)
    return hysteresis_spec(params, dt, args.param, args.start, args.stop, args.points,
                           args.t_settle, args.window, args.tol)


def fields(pt: WarmPoint) -> dict[str, Any]:
    """A computed point as the stored ones are read back (NaN kept)."""
    return {"value": pt.value, "regime": pt.regime, "amplitude": pt.amplitude,
            "detail": pt.detail, "growth": pt.growth, "jumped": pt.jumped}


def record(pt: Mapping[str, Any]) -> dict[str, Any]:
    """A point as ``--json`` prints it (NaN as null: slopetui.json_text)."""
    return {"value": pt["value"], "regime": pt["regime"], "amplitude": pt["amplitude"],
            "detail": pt["detail"], "growth": pt["growth"], "jumped": pt["jumped"]}


def _line(direction: str, param: str, pt: Mapping[str, Any]) -> str:
    growth = pt["growth"]
    note = ""
    if pt["jumped"]:
        note = f"  rest unstable (growth {growth:+.2e}/t): kicked" if math.isfinite(growth) \
            else "  rest unstable: kicked"
    elif math.isfinite(growth):
        note = f"  growth {growth:+.2e}/t"
    return (f"{direction:<4} {param} = {pt['value']:<10.6g} {terminal_safe(pt['regime']):<12} "
            f"amplitude {pt['amplitude']:<10.4g} {terminal_safe(pt['detail'])}{note}")


def _changes(param: str, up: Sequence[Mapping[str, Any]], down: Sequence[Mapping[str, Any]],
             found: Mapping[str, Any], tol: float | None, step: float) -> None:
    """Where each branch changes regime: refined, with its grid bracket (the last value on
    the old attractor, the first on the new); a sweep stored before brackets were kept has
    the grid's value alone. Then which branch ended early (a run that left the finite
    range)."""
    for name, key in (("up branch changes regime at", "onset_up"),
                      ("down branch changes regime at", "offset_down")):
        value, before, after = found[key], found.get(f"{key}_before"), found.get(f"{key}_after")
        if value is None:
            print(f"{name.split(' changes')[0]} keeps its regime throughout")
        elif before is None or after is None:
            print(f"{name} {param} = {value:.6g} (grid step {step:.3g})")
        else:
            print(f"{name} {param} = {value:.6g} (refined to {tol:.2g} relative; bracket: last "
                  f"on the old attractor {before:.6g}, first on the new {after:.6g})")
    if up and not down:
        print("the up branch ended early: " + terminal_safe(up[-1]["detail"]))
    elif len(down) < len(up):
        print("the down branch ended early: " + terminal_safe(down[-1]["detail"]))


def _plot(param: str, up: Sequence[Mapping[str, Any]], down: Sequence[Mapping[str, Any]],
          title: str) -> None:
    size = shutil.get_terminal_size((100, 30))
    print(render_hysteresis(param, up, down, title=title, width=size.columns,
                            height=max(size.lines - 2, 12)))


def _submit(args: argparse.Namespace, spec: HysteresisSpec) -> int:
    sid = submit(open_db(args), spec)
    return say_queued(args.json, "hysteresis sweep", sid, f"slopetui hysteresis --show {sid}")


def _show(args: argparse.Namespace) -> int:
    args.show = int_arg("show", args.show, 1, note=" (a hysteresis sweep id)")
    sweep = hysteresis_of(open_db(args), args.show)
    if sweep is None:
        raise UsageError(f"no hysteresis sweep {args.show} in this store")
    row, param = sweep.row, terminal_safe(sweep.param)  # stored text, escaped as the rest
    if args.json:
        print(json_text({**sweep.summary(), "up": [record(p) for p in sweep.up],
                         "down": [record(p) for p in sweep.down],
                         # as a sweep computed now says it (args.param's value at --from);
                         # the engine it was computed with
                         **computed_at({**params_of(row), row.param: row.start},
                                       {"method": "rk4", "dt": row.dt, "t_settle": row.t_settle,
                                        "window": row.window, "tol": row.tol}, row.engine)}))
        return 0
    print(f"hysteresis sweep {sweep.id} in {param} from {row.start:g} to {row.stop:g}, "
          f"{row.n_points} points each way: {terminal_safe(row.status)}, {row.n_done} points, "
          f"{row.runtime_s:.1f} s")
    for pt in sweep.points:
        print(_line(pt["direction"], param, pt))
    _status(sweep)
    if args.plot:
        _plot(param, sweep.up, sweep.down, f"hysteresis sweep {sweep.id} in {param}")
    return 0


def _status(sweep: StoredHysteresis) -> None:
    """Where each branch changes regime once done; else the status and the error's last
    line (what went wrong)."""
    row = sweep.row
    if row.status == "done":
        step = abs(row.stop - row.start) / (row.n_points - 1)
        _changes(terminal_safe(sweep.param), sweep.up, sweep.down, asdict(row), row.tol, step)
    elif row.error:
        print(f"{terminal_safe(row.status)}: "
              f"{terminal_safe(str(row.error).strip().splitlines()[-1])}")
    else:
        print(f"{terminal_safe(row.status)}: {row.n_done} of {2 * row.n_points} points so far")


def handle(args: argparse.Namespace) -> int:
    if args.show is not None:
        if args.submit:
            raise UsageError("--show reads a stored sweep and --submit queues one: not both")
        return _show(args)
    for flag, given in (("--param", args.param), ("--from", args.start), ("--to", args.stop)):
        if given is None:
            raise UsageError(f"the following argument is required: {flag} (or --show ID to "
                             "print a stored sweep)")
    return _compute_or_submit(args)


def _compute_or_submit(args: argparse.Namespace) -> int:
    # numba and scipy (~0.5 s) load here, for a sweep computed or submitted: `--show`
    # (a stored sweep's lines and plot) never needs them
    from core.hysteresis import hysteresis

    try:
        spec = _checked(args)
    except ParameterError as exc:
        print(f"slopetui hysteresis: error: {exc}", file=sys.stderr)
        return 2
    if args.submit:
        return _submit(args, spec)
    params, dt, start, stop = spec.params, spec.dt, spec.start, spec.stop
    t_settle, window, tol, points = spec.t_settle, spec.window, spec.tol, spec.n_points
    say_if_compiling("hysteresis")
    t0 = time.process_time()

    def say(direction: str, pt: WarmPoint) -> None:
        if not args.json:
            print(_line(direction, args.param, fields(pt)), flush=True)

    result = hysteresis(params, args.param, start, stop, points, dt, t_settle, window, say, tol)
    took = time.process_time() - t0
    up, down = [fields(p) for p in result.up], [fields(p) for p in result.down]
    found = {**transition_fields("onset_up", result.onset),
             **transition_fields("offset_down", result.offset)}
    if args.json:
        print(json_text({"param": args.param, "up": [record(p) for p in up],
                         "down": [record(p) for p in down], **found,
                         "dt": dt, "t_settle": t_settle, "window": window, "tol": tol,
                         "runtime_s": took,
                         # RK4 is the sweep's map (core.period_map); params: the other seven
                         # as given, args.param's at --from
                         **computed_at(params.with_(**{args.param: start}),
                                       {"method": "rk4", "dt": dt, "t_settle": t_settle,
                                        "window": window, "tol": tol})}))
        return 0
    _changes(args.param, up, down, found, tol, abs(stop - start) / (points - 1))
    print(f"{len(up) + len(down)} points, {took:.1f} s")
    if args.plot:
        _plot(args.param, up, down, f"hysteresis in {args.param}")
    return 0
