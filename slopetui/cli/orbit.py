"""``slopetui orbit``: the periodic orbit a point settles on, and its Floquet multipliers."""

from __future__ import annotations

import argparse
import sys
import time
from typing import TYPE_CHECKING

from core.classify import maxima_words
from core.floquet import UNIT_TOL
from core.orbit import Grid
from core.orbit_seed import state_from_carried
from core.orbit_step import step_check
from core.params import PARAM_NAMES, ParameterError, Params
from core.periodic_orbit import OrbitError, find_orbit
from slopetui.cli.arguments.orbit import MAX_SLIPS
from slopetui.json_text import json_text
from slopetui.provenance import computed_at
from slopetui.queue.warm_up import say_if_compiling
from slopetui.sweeps import orbit_point
from slopetui.sweeps.orbit_point import seed_length

if TYPE_CHECKING:
    from core.history import CarriedState
    from core.orbit_step import StepCheck
    from core.periodic_orbit import Orbit

#: Multipliers printed and in --json (the leading ones, by modulus).
SHOWN = 10


def point_of(args: argparse.Namespace) -> tuple[Params, float]:
    """The validated parameters and step; raises ParameterError naming the field."""
    return orbit_point.point_of(vars(args))


def record(o: Orbit, check: StepCheck, runtime_s: float, t_seed: float) -> dict[str, object]:
    """The --json object: the orbit, its multipliers and how it was found, the orbit at
    half the step (``step_check``: core.orbit_step), then what it was computed at
    (``params``, ``solver``, ``engine``: slopetui.provenance)."""
    m = o.multipliers
    values = m.values[:max(SHOWN, m.flow_index + 1)]
    return {
        "period": o.period,
        "amplitude": o.amplitude,
        "maxima_per_period": o.maxima_per_period,
        "slips": o.slips,
        "stable": m.verdict() == "stable",
        "stability": m.verdict(),
        "multipliers": [[float(v.real), float(v.imag)] for v in values],
        "moduli": [float(abs(v)) for v in values],
        "flow_multiplier": [m.flow.real, m.flow.imag],
        "translation_multiplier": m.translation,
        "dt": o.grid.dt,
        "newton_steps": o.newton_steps,
        "residual": o.residual,
        "step_check": check.record(),
        "runtime_s": runtime_s,
        # RK4 is the orbit's map (core.period_map); t_seed: the simulation of its first guess
        **computed_at(o.params, {"method": "rk4", "dt": o.grid.dt, "t_seed": t_seed}),
    }


def render(o: Orbit, check: StepCheck, runtime_s: float) -> str:
    m = o.multipliers
    p = o.params
    lines = [
        f"point        a={p.a:g} b={p.b:g} c={p.c:g} d={p.d:g} k={p.k:g} v={p.v:g} tau={p.tau:g}",
        f"orbit        period {o.period:.10g}, amplitude {o.amplitude:.6g} (peak-to-peak m_y), "
        f"{maxima_words(o.maxima_per_period)} per period"
        + (f" (the equally spaced {o.slips}-slip orbit)" if o.slips > 1 else ""),
        f"stability    {m.verdict()} ({m.unstable_count} multipliers outside the unit circle"
        + (f"; one within {UNIT_TOL:g} of it: undecided at this accuracy)"
           if m.verdict() == "marginal" else ")"),
        f"checks       flow multiplier {abs(m.flow - 1):.1e} from 1, translation multiplier "
        f"{m.translation:.15g}",
        f"step check   {check.text(maxima_words(check.maxima_per_period) + ' per period')}",
        f"newton       {o.newton_steps} steps, residual {o.residual:.1e}, RK4 at dt = {o.grid.dt:g}; "
        f"{runtime_s:.2f} s (with the step check)",
        "multipliers  (leading, by modulus; * the flow's)",
    ]
    for i, v in enumerate(m.values[:max(SHOWN, m.flow_index + 1)]):
        mark = "*" if i == m.flow_index else " "
        lines.append(f"  {mark} {v.real:+.8f} {v.imag:+.8f}i   |mu| = {abs(v):.8f}")
    return "\n".join(lines)


def slips_of(text: str | None) -> int | None:
    """--slips as a count, None when not given; ParameterError naming it otherwise."""
    if text is None:
        return None
    if not (text.isascii() and text.isdigit() and 1 <= int(text) <= MAX_SLIPS):
        raise ParameterError("slips", text, f"an integer from 1 to {MAX_SLIPS}")
    return int(text)


def run_start(args: argparse.Namespace) -> tuple[argparse.Namespace, CarriedState | None]:
    """--from-run ID: the run's parameters under the flags given, and its final state
    (recomputed, slopetui.sweeps.carried); ParameterError naming the field."""
    if args.from_run is None:
        return args, None
    from slopetui.cli.options import open_db
    from slopetui.sweeps.carried import MAX_RUN_ID, final_state_of
    from slopetui.sweeps.recompute import load_run
    text = args.from_run
    if not (text.isascii() and text.isdigit() and 1 <= int(text) <= MAX_RUN_ID):
        raise ParameterError("from-run", text, f"a run id from 1 to {MAX_RUN_ID}")
    db = open_db(args)
    run = load_run(db, int(text))
    if run is None:
        raise ParameterError("from-run", text, "the id of a run in this store")
    params, _ = run.inputs()
    given = {n: getattr(args, n) for n in PARAM_NAMES if getattr(args, n) is not None}
    merged = argparse.Namespace(**{**vars(args), **{n: repr(getattr(params, n)) for n in PARAM_NAMES},
                                   **given})
    if float(merged.tau) != params.tau:
        raise ParameterError("tau", merged.tau, f"the run's, {params.tau:g} (its state spans "
                                                "one delay)")
    return merged, final_state_of(db, int(text))


def handle(args: argparse.Namespace) -> int:
    try:
        slips = slips_of(args.slips)
        args, carried = run_start(args)
        params, dt = point_of(args)
        t_seed = seed_length(args.t_seed, params, dt)
    except ParameterError as exc:
        print(f"slopetui orbit: error: {exc}", file=sys.stderr)
        return 2
    say_if_compiling("orbit")
    t0 = time.process_time()
    try:
        start = None if carried is None else state_from_carried(carried, Grid.of(params, dt))
        orbit = find_orbit(params, dt, t_seed, slips=slips, start=start)
    except OrbitError as exc:
        print(f"slopetui orbit: no orbit: {exc}", file=sys.stderr)
        return 1
    check = step_check(orbit)
    took = time.process_time() - t0
    print(json_text(record(orbit, check, took, t_seed)) if args.json
          else render(orbit, check, took))
    return 0
