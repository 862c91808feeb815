"""``slopetui orbit``: the periodic orbit a point settles on, and its Floquet multipliers."""

from __future__ import annotations

import argparse
import sys
import time
from typing import TYPE_CHECKING

from core.classify import maxima_words
from core.params import PARAM_NAMES, ParameterError, Params
from core.periodic_orbit import OrbitError, find_orbit
from slopetui.json_text import json_text
from slopetui.queue.warm_up import say_if_compiling
from slopetui.sweeps import orbit_point
from slopetui.sweeps.orbit_point import seed_length

if TYPE_CHECKING:
    from core.periodic_orbit import Orbit

#: Multipliers printed and in --json (the leading ones, by modulus).
SHOWN = 10


def point_of(args: argparse.Namespace) -> tuple[Params, float]:
    """The validated parameters and step; raises ParameterError naming the field."""
    return orbit_point.point_of(vars(args))


def record(o: Orbit, runtime_s: float) -> dict[str, object]:
    """The --json object: the orbit, its multipliers and how it was found."""
    m = o.multipliers
    values = m.values[:SHOWN]
    return {
        "period": o.period,
        "amplitude": o.amplitude,
        "maxima_per_period": o.maxima_per_period,
        "stable": o.stable,
        "multipliers": [[float(v.real), float(v.imag)] for v in values],
        "moduli": [float(abs(v)) for v in values],
        "flow_multiplier": [m.flow.real, m.flow.imag],
        "translation_multiplier": m.translation,
        "dt": o.grid.dt,
        "newton_steps": o.newton_steps,
        "residual": o.residual,
        "runtime_s": runtime_s,
        "params": {n: getattr(o.params, n) for n in PARAM_NAMES},
    }


def render(o: Orbit, runtime_s: float) -> str:
    m = o.multipliers
    p = o.params
    lines = [
        f"point        a={p.a:g} b={p.b:g} c={p.c:g} d={p.d:g} k={p.k:g} v={p.v:g} tau={p.tau:g}",
        f"orbit        period {o.period:.10g}, amplitude {o.amplitude:.6g} (peak-to-peak m_y), "
        f"{maxima_words(o.maxima_per_period)} per period",
        f"stability    {'stable' if o.stable else 'unstable'} "
        f"({m.unstable_count} multipliers outside the unit circle)",
        f"checks       flow multiplier {abs(m.flow - 1):.1e} from 1, translation multiplier "
        f"{m.translation:.15g}",
        f"newton       {o.newton_steps} steps, residual {o.residual:.1e}, RK4 at dt = {o.grid.dt:g}; "
        f"{runtime_s:.2f} s",
        "multipliers  (leading, by modulus; * the flow's)",
    ]
    for i, v in enumerate(m.values[:SHOWN]):
        mark = "*" if i == m.flow_index else " "
        lines.append(f"  {mark} {v.real:+.8f} {v.imag:+.8f}i   |mu| = {abs(v):.8f}")
    return "\n".join(lines)


def handle(args: argparse.Namespace) -> int:
    try:
        params, dt = point_of(args)
        t_seed = seed_length(args.t_seed, params, dt)
    except ParameterError as exc:
        print(f"slopetui orbit: error: {exc}", file=sys.stderr)
        return 2
    say_if_compiling("orbit")
    t0 = time.process_time()
    try:
        orbit = find_orbit(params, dt, t_seed)
    except OrbitError as exc:
        print(f"slopetui orbit: no orbit: {exc}", file=sys.stderr)
        return 1
    took = time.process_time() - t0
    print(json_text(record(orbit, took)) if args.json else render(orbit, took))
    return 0
