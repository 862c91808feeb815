"""``slopetui hysteresis``: follow the attractor along one parameter, up and then down,
each point warm-started from the final state of the one before (core.hysteresis)."""

from __future__ import annotations

import argparse
import json
import math
import shutil
import sys
import time
from typing import TYPE_CHECKING, Any

from core.params import PARAM_NAMES, ParameterError, Params
from slopetui.cli.orbit import add_point_options, point_of

if TYPE_CHECKING:
    from core.hysteresis import WarmPoint

#: Parameters a warm-started sweep can follow: not tau (the state's history is one delay
#: long and would change size) nor delta (which only places the first point's start).
FOLLOWABLE = tuple(n for n in PARAM_NAMES if n not in ("tau", "delta"))


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("hysteresis", help="warm-started sweep up and down one parameter: "
                                          "where the outcome depends on the path",
                       description="Along --param from --from to --to and back, each point "
                                   "starts from the final state of the previous one (the five "
                                   "variables and m_x, m_y over the last delay), so each branch "
                                   "follows its attractor until it disappears. A rest state "
                                   "whose perturbations grow (measured along the simulation) is "
                                   "kicked off. Prints both branches and where each changes "
                                   "regime; the first point starts from eq. 19 (--delta).")
    add_point_options(p)
    p.add_argument("--param", required=True, choices=FOLLOWABLE, help="the parameter to follow")
    p.add_argument("--from", dest="start", required=True, metavar="X", help="first value")
    p.add_argument("--to", dest="stop", required=True, metavar="X", help="last value")
    p.add_argument("--points", type=int, default=40, metavar="N",
                   help="values from --from to --to, ends included (default 40, 2 to 2000)")
    p.add_argument("--t-settle", dest="t_settle", type=float, default=None, metavar="T",
                   help="time integrated at each point (default 6000)")
    p.add_argument("--window", type=float, default=None, metavar="T",
                   help="analysis window at the end of each point (default 1000)")
    p.add_argument("--plot", action="store_true", help="also draw both branches")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(handler=handle)


def _number(flag: str, text: str, params: Params, name: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise ParameterError(flag, text, "a finite number") from None
    if not math.isfinite(value):
        raise ParameterError(flag, text, "a finite number")
    params.with_(**{name: value})  # raises ParameterError naming the parameter's range
    return value


def _checked(args: argparse.Namespace) -> tuple[Params, float, float, float, float, float]:
    from core.hysteresis import T_SETTLE, WINDOW
    params, dt = point_of(args)
    start = _number("from", args.start, params, args.param)
    stop = _number("to", args.stop, params, args.param)
    if start == stop:
        raise ParameterError("to", args.stop, f"a value other than --from = {start:g}")
    if not 2 <= args.points <= 2000:
        raise ParameterError("points", args.points, "an integer from 2 to 2000")
    t_settle = T_SETTLE if args.t_settle is None else args.t_settle
    window = min(WINDOW, t_settle) if args.window is None else args.window
    if not (math.isfinite(t_settle) and t_settle >= 10 * params.tau and t_settle <= 1e6):
        raise ParameterError("t-settle", t_settle, f"a number from 10 tau = {10 * params.tau:g} "
                                                   "to 1e6")
    if not (math.isfinite(window) and 10 * dt <= window <= t_settle):
        raise ParameterError("window", window, f"a number from 10 dt to --t-settle = {t_settle:g}")
    return params, dt, start, stop, t_settle, window


def record(pt: WarmPoint) -> dict[str, Any]:
    def finite(x: float) -> float | None:
        return x if math.isfinite(x) else None
    return {"value": pt.value, "regime": pt.regime, "amplitude": finite(pt.amplitude),
            "detail": pt.detail, "growth": finite(pt.growth), "jumped": pt.jumped}


def _line(direction: str, param: str, pt: WarmPoint) -> str:
    note = ""
    if pt.jumped:
        note = f"  rest unstable (growth {pt.growth:+.2e}/t): kicked" if math.isfinite(pt.growth) \
            else "  rest unstable: kicked"
    elif math.isfinite(pt.growth):
        note = f"  growth {pt.growth:+.2e}/t"
    return (f"{direction:<4} {param} = {pt.value:<10.6g} {pt.regime:<12} amplitude "
            f"{pt.amplitude:<10.4g} {pt.detail}{note}")


def handle(args: argparse.Namespace) -> int:
    try:
        params, dt, start, stop, t_settle, window = _checked(args)
    except ParameterError as exc:
        print(f"slopetui hysteresis: error: {exc}", file=sys.stderr)
        return 2
    from core.hysteresis import hysteresis
    t0 = time.process_time()

    def say(direction: str, pt: WarmPoint) -> None:
        if not args.json:
            print(_line(direction, args.param, pt), flush=True)

    result = hysteresis(params, args.param, start, stop, args.points, dt, t_settle, window, say)
    took = time.process_time() - t0
    if args.json:
        print(json.dumps({"param": args.param, "up": [record(p) for p in result.up],
                          "down": [record(p) for p in result.down],
                          "onset_up": result.onset_up, "offset_down": result.offset_down,
                          "dt": dt, "t_settle": t_settle, "window": window,
                          "runtime_s": took}))
        return 0
    step = abs(stop - start) / (args.points - 1)
    for name, value in (("up branch changes regime at", result.onset_up),
                        ("down branch changes regime at", result.offset_down)):
        print(f"{name} {args.param} = {value:.6g} (grid step {step:.3g})" if value is not None
              else f"{name.split(' changes')[0]} keeps its regime throughout")
    if len(result.down) < len(result.up) or not result.down:
        print("the up branch ended early: " + result.up[-1].detail)
    print(f"{len(result.up) + len(result.down)} points, {took:.1f} s")
    if args.plot:
        from slopetui.plots.hysteresis_plot import render_hysteresis
        size = shutil.get_terminal_size((100, 30))
        print(render_hysteresis(args.param, [record(p) for p in result.up],
                                [record(p) for p in result.down],
                                title=f"hysteresis in {args.param}", width=size.columns,
                                height=max(size.lines - 2, 12)))
    return 0
