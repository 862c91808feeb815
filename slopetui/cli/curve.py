"""``slopetui continue --param P --param2 Q``: a curve in two parameters, computed here
(core.curve_start: the same walk a worker runs for ``--submit``). From a fold of cycles
(``--from-fold``) the fold curve with its codimension-two points (cusp, Bautin at its end
on the Hopf curve, fold-flip, fold-torus, 1:1 resonance); from the Hopf point
(``--from-hopf``) the Hopf curve with its first Lyapunov coefficient l1 and the Bautin
points where l1 changes sign; from a branch's first real period doubling (``--from-pd``)
the period-doubling curve (resonance-1:2, flip-torus, fold-flip along it)."""

from __future__ import annotations

import argparse
import sys
import time
from typing import TYPE_CHECKING, Any

from slopetui.json_text import json_text
from slopetui.provenance import computed_at
from slopetui.sweeps.curve_records import (
    codim2_record,
    curve_record,
    curve_solver,
    print_codim2,
    print_curve_point,
)

if TYPE_CHECKING:
    from core.curve_start import CurveSpec


def run_curve(args: argparse.Namespace, spec: CurveSpec) -> int:
    """Compute the curve here and print it (a line per point, or one JSON object with
    --json)."""
    from core.curve_start import start
    from core.orbit import OrbitError
    from slopetui.queue.warm_up import say_if_compiling

    say_if_compiling("continue")
    t0 = time.process_time()
    try:
        walk = start(spec)
    except OrbitError as exc:
        print(f"slopetui continue: no curve: {exc}", file=sys.stderr)
        return 1
    points: list[dict[str, Any]] = []
    while (saved := walk.step()) is not None:
        points.append(curve_record(spec.name, spec.second, saved, spec.start))
        if not args.json:
            print_curve_point(spec.name, spec.second, points[-1])
    found = [codim2_record(spec.name, spec.second, c) for c in walk.found()]
    took = time.process_time() - t0
    record = {"param": spec.name, "param2": spec.second, "start": spec.start,
              "curve": points, "bifurcations": found, "end": walk.end, "runtime_s": took,
              **computed_at(spec.params, curve_solver(spec.dt, spec.start, spec.max_points,
                                                         spec.max_step, spec.to),
                            start=(spec.name, points[0][spec.name] if points else None))}
    if args.json:
        print(json_text(record))
        return 0
    print(f"end: {walk.end} ({len(points)} points, {took:.1f} s CPU)")
    print_codim2(spec.name, spec.second, found)
    return 0
