"""``slopetui continue --param P --param2 Q``: a curve in two parameters. From a fold of
cycles (``--from-fold``) the fold curve, with its codimension-two points (cusp, Bautin at
its end on the Hopf curve, fold-flip, fold-torus, 1:1 resonance); from the Hopf point
(``--from-hopf``) the Hopf curve with its first Lyapunov coefficient l1 and the Bautin
points where l1 changes sign."""

from __future__ import annotations

import argparse
import itertools
import sys
import time
from typing import TYPE_CHECKING, Any

from slopetui.display_text import terminal_safe
from slopetui.json_text import json_text
from slopetui.provenance import computed_at
from slopetui.sweeps.curve_request import hopf_points

if TYPE_CHECKING:
    from slopetui.sweeps.curve_request import CurveSpec


def _solver(spec: CurveSpec, dt: float) -> dict[str, Any]:
    return {"method": "rk4", "dt": dt, "curve": spec.start, "points": spec.max_points,
            "max_step": spec.max_step, "to2": spec.to}


def _fold_curve(spec: CurveSpec) -> dict[str, Any]:
    from core.fold_continuation import codim2_points, start_at_fold, walk

    curve = start_at_fold(spec.params, (spec.name, spec.second), spec.to, spec.dt,
                          max_step=spec.max_step)
    points = []
    for pt in walk(curve, spec.to, spec.max_points):
        points.append({spec.name: pt.first, spec.second: pt.second, "period": pt.period,
                       "amplitude": pt.amplitude, "stable": bool(pt.multipliers.verdict() !=
                                                                 "unstable"),
                       "leading_multiplier": _pair(_leading(pt.multipliers))})
    found = [{"type": c.type, spec.name: c.first, spec.second: c.second,
              "period": c.period, "note": c.note} for c in codim2_points(curve)]
    return {"curve": points, "bifurcations": found, "end": curve.end,
            "dt_range": _dt_range(curve)}


def _leading(m: Any) -> complex:
    """The largest multiplier but the two a fold has at +1."""
    from core.fold_continuation import fold_others

    others = fold_others(m)
    return complex(others[0]) if others.size else 0j


def _pair(mu: complex) -> list[float]:
    return [mu.real, mu.imag]


def _dt_range(curve: Any) -> list[float]:
    """The grid's dt at the curve's ends (dt follows tau when tau is on the curve)."""
    if "tau" not in curve.names:
        return [curve.dt0, curve.dt0]
    i = curve.names.index("tau")
    taus = [p.first if i == 0 else p.second for p in curve.points]
    return [min(taus) / curve.n_delay, max(taus) / curve.n_delay] if taus else []


def _hopf_curve(spec: CurveSpec) -> dict[str, Any]:
    import numpy as np

    from core.lyapunov_coefficient import bautin, hopf_curve

    names = (spec.name, spec.second)
    here = getattr(spec.params, spec.second)
    count = hopf_points(here, spec.to, spec.max_step)
    points = list(hopf_curve(spec.params, names, np.linspace(here, spec.to, count), spec.dt))
    found = []
    for a, b in itertools.pairwise(points):
        if a.l1 * b.l1 < 0:
            bp = bautin(spec.params, names, a, b, spec.dt)
            found.append({"type": "bautin", spec.name: bp.first, spec.second: bp.second,
                          "period": bp.period, "note": "l1 = 0 on the Hopf curve"})
    return {"curve": [{spec.name: p.first, spec.second: p.second, "period": p.period,
                       "l1": p.l1, "criticality": "supercritical" if p.l1 < 0 else "subcritical"}
                      for p in points],
            "bifurcations": found, "end": f"reached {spec.second} = {spec.to:g}",
            "dt_range": [spec.dt, spec.dt]}


def run_curve(args: argparse.Namespace, spec: CurveSpec) -> int:
    """Compute the curve here and print it (lines, or one JSON object with --json)."""
    from core.orbit import OrbitError
    from slopetui.queue.warm_up import say_if_compiling

    say_if_compiling("continue")
    t0 = time.process_time()
    try:
        out = _fold_curve(spec) if spec.start == "fold" else _hopf_curve(spec)
    except OrbitError as exc:
        print(f"slopetui continue: no curve: {exc}", file=sys.stderr)
        return 1
    took = time.process_time() - t0
    record = {"param": spec.name, "param2": spec.second, "start": spec.start, **out,
              "runtime_s": took,
              **computed_at(spec.params, _solver(spec, spec.dt),
                            start=(spec.name, out["curve"][0][spec.name] if out["curve"]
                                   else None))}
    if args.json:
        print(json_text(record))
        return 0
    for point in out["curve"]:
        extra = (f"l1 {point['l1']:+.6g} ({point['criticality']})" if "l1" in point else
                 f"amplitude {point['amplitude']:.6g}")
        print(f"{spec.name} = {point[spec.name]:<14.10g} {spec.second} = "
              f"{point[spec.second]:<12.8g} period {point['period']:<12.8g} {extra}")
    print(f"end: {terminal_safe(out['end'])} ({len(out['curve'])} points, {took:.1f} s CPU)")
    for b in out["bifurcations"]:
        print(f"{b['type']:<14} {spec.name} = {b[spec.name]:.8g}, {spec.second} = "
              f"{b[spec.second]:.8g}, period {b['period']:.8g}  ({terminal_safe(b['note'])})")
    if not out["bifurcations"]:
        print("no codimension-two point on this curve")
    return 0
