"""``slopetui run``: integrate and classify one parameter point."""

from __future__ import annotations

import argparse
import json
import math
import sys

from core import (
    METHODS,
    PARAM_NAMES,
    ParameterError,
    Params,
    SolverSettings,
    friction_warnings,
    run_point,
)
from core.point import PointResult
from core.solve import make_grid

#: The keys of ``--json``, in order (the issue's contract), plus a few extras after them.
JSON_KEYS = ("regime", "lambda_max", "lambda_err", "amplitude", "period", "peaks", "drift",
             "t_blowup", "runtime_s")

PARAM_HELP = {
    "a": "friction coefficient a (default 3.2)",
    "b": "friction coefficient b (default 7.2)",
    "c": "friction coefficient c (default 4.8)",
    "d": "noise intensity d >= 0 (default 1e-4)",
    "k": "spring stiffness k >= 0 (default 10)",
    "v": "steady sliding velocity v (default 0.1)",
    "tau": "delay tau >= 0 (default 10)",
    "delta": "initial offset delta of eq. 19 (default 0.1)",
}


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("run", help="run one parameter point and print its regime",
                       description="Integrate eqs. 6a-6e at one point, classify the analysis "
                                   "window and estimate lambda_max.")
    for name in PARAM_NAMES:
        p.add_argument(f"--{name.replace('_', '-')}", dest=name, metavar="X", help=PARAM_HELP[name])
    p.add_argument("--method", choices=METHODS, default="euler",
                   help="euler (paper-faithful, default) or rk4 (4th order)")
    p.add_argument("--dt", metavar="X", help="time step (default 1e-3 for euler, 1e-2 for rk4)")
    p.add_argument("--t-end", dest="t_end", metavar="X", default="1e5",
                   help="end time of the run (default 1e5)")
    p.add_argument("--window", metavar="X", default="1000",
                   help="analysis window at the end of the run (default 1000)")
    p.add_argument("--no-lyap", dest="lyap", action="store_false", help="skip lambda_max")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(handler=handle)


def parse_inputs(args: argparse.Namespace) -> tuple[Params, SolverSettings]:
    """Build validated Params and SolverSettings from the flags; raises ParameterError."""
    given = {n: getattr(args, n) for n in PARAM_NAMES if getattr(args, n) is not None}
    params = Params(**given)  # type: ignore[arg-type]  # strings are checked and coerced
    settings = SolverSettings(method=args.method, dt=args.dt, t_end=args.t_end,
                              window=args.window, lyap=args.lyap)
    make_grid(params, settings)  # validates the pair: dt against tau
    return params, settings


def json_safe(value: object) -> object:
    """JSON has no NaN or infinity: they become null."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, list):
        return [json_safe(v) for v in value]
    return value


def render_text(r: PointResult) -> str:
    s, rec = r.summary, r.as_record()
    p = r.params
    lam = r.lyap.format() if r.lyap else "not computed"
    peaks = ", ".join(f"{v:.6g}" for v in s.peaks) or "none"
    lines = [
        f"point      a={p.a:g} b={p.b:g} c={p.c:g} d={p.d:g} k={p.k:g} v={p.v:g} "
        f"tau={p.tau:g} delta={p.delta:g}",
        f"solver     {r.settings.method}, dt={rec['dt']:g}, t_end={rec['t_end']:g}, "
        f"window={r.settings.window:g}",
        f"regime     {s.regime} ({s.detail})",
        f"lambda_max {lam}",
        f"amplitude  {s.amplitude:.6g}  (peak-to-peak of m_y)",
        f"period     {s.period:.6g}  ({s.period_count} peak cluster{'s' if s.period_count > 1 else ''})"
        if s.period_count > 0 else f"period     {s.period:.6g}",
        f"peaks      {peaks}",
        f"frequency  {s.frequency:.6g}",
        f"drift      {s.drift:.6g}  (mean dm_x/dt over the window)",
    ]
    if r.t_blowup is not None:
        lines.append(f"blow-up    at t = {r.t_blowup:.6g}")
    lines.append(f"runtime    {r.runtime_s:.3f} s")
    return "\n".join(lines)


def handle(args: argparse.Namespace) -> int:
    try:
        params, settings = parse_inputs(args)
    except ParameterError as exc:
        print(f"slopetui run: error: {exc}", file=sys.stderr)
        return 2
    for w in friction_warnings(params):
        print(f"slopetui run: warning: {w}", file=sys.stderr)
    result = run_point(params, settings)
    if args.json:
        rec = result.as_record()
        ordered = {k: rec[k] for k in JSON_KEYS} | {k: v for k, v in rec.items() if k not in JSON_KEYS}
        print(json.dumps({k: json_safe(v) for k, v in ordered.items()}))
    else:
        print(render_text(result))
    return 0
