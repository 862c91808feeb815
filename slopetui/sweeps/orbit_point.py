"""The point, step and seed of an orbit computation, checked from text: the one check of
``slopetui orbit``'s, ``continue``'s and ``hysteresis``'s flags and of the application's
analysis forms, so that both refuse the same input with the same one line (a
ParameterError naming the field and its range). And the orbit itself, computed for
either face. No UI here; numpy and numba load only when an orbit is computed.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING

from core.params import PARAM_NAMES, ParameterError, Params

if TYPE_CHECKING:
    from core.orbit_step import StepCheck
    from core.periodic_orbit import Orbit

#: The seed simulation's shortest length: returns are looked for in its second half,
#: which must hold a few oscillations (the basic period is about 10 time units); below
#: it the search read an empty window (a ValueError from numpy).
MIN_T_SEED = 100.0

#: Its most steps: the seed's trajectory is held whole, 5 float64 rows (40 bytes a step),
#: so 5e7 steps take 2 GB, as a run may (core.solve); beyond, MemoryError or hours.
MAX_SEED_STEPS = 5e7

#: core.periodic_orbit.SEED_SPAN (not imported: it brings numpy and numba to the faces):
#: the seed runs at least 4 tau + this long.
SEED_SPAN = 600.0


def point_of(values: Mapping[str, object]) -> tuple[Params, float]:
    """The validated parameters (``values``' a ... delta; None or absent: the paper's
    default, "" refused) and RK4 step (``values["dt"]``, text); raises ParameterError
    naming the field."""
    given = {n: values[n] for n in PARAM_NAMES if values.get(n) is not None}
    params = Params(**given)  # type: ignore[arg-type]  # text: Params checks and converts
    if params.tau <= 0.0:  # before dt, whose range it sets
        raise ParameterError("tau", params.tau, "> 0 (periodic orbits of this model need a delay)")
    text = values.get("dt")
    try:
        dt = float(str(text))
    except ValueError:
        raise ParameterError("dt", text, "a number in (0, tau]") from None
    if not (math.isfinite(dt) and 0 < dt <= params.tau):
        raise ParameterError("dt", text, f"a number in (0, tau = {params.tau:g}]")
    if params.tau / dt > 1e5:
        raise ParameterError("dt", text, f"at least tau / 1e5 = {params.tau / 1e5:g} "
                                         "(the orbit's state holds 2 tau / dt numbers)")
    return params, dt


def seed_steps(params: Params, dt: float, t_seed: float) -> float:
    """The steps of dt the seed simulation takes (at least 4 tau + SEED_SPAN long:
    core.periodic_orbit.find_orbit)."""
    return max(t_seed, 4 * params.tau + SEED_SPAN) / dt


def check_seed_steps(params: Params, dt: float, t_seed: float) -> None:
    """A ParameterError naming dt when the seed simulation (t_seed, and at least 4 tau +
    600: core.periodic_orbit.find_orbit) would take more than MAX_SEED_STEPS of it."""
    length = max(t_seed, 4 * params.tau + SEED_SPAN)
    if length > MAX_SEED_STEPS * dt:
        raise ParameterError("dt", dt, f"at least {length:g} / {MAX_SEED_STEPS:g} = "
                                       f"{length / MAX_SEED_STEPS:g} (the seed simulation of "
                                       f"{length:g} time units is held in memory)")


def seed_length(text: object, params: Params, dt: float) -> float:
    """The seed's length (``t-seed``) as a number the seed simulation can run;
    ParameterError naming it, or dt when even the shortest seed is too many steps of it
    (check_seed_steps)."""
    check_seed_steps(params, dt, MIN_T_SEED)
    high = MAX_SEED_STEPS * dt
    allowed = f"a number from {MIN_T_SEED:g} to {high:g} ({MAX_SEED_STEPS:g} steps of dt = {dt:g})"
    try:
        value = float(str(text))
    except ValueError:
        raise ParameterError("t-seed", text, allowed) from None
    if not (math.isfinite(value) and MIN_T_SEED <= value <= high):  # -5: a ValueError, inf:
        raise ParameterError("t-seed", text, allowed)               # an OverflowError before
    return value


def compute_orbit(params: Params, dt: float, t_seed: float) -> tuple[Orbit, StepCheck]:
    """The orbit a simulation from eq. 19 settles on, corrected by shooting, with its
    multipliers (core.periodic_orbit.find_orbit), and the same orbit at half the step
    (core.orbit_step); OrbitError where there is none."""
    from core.orbit_step import step_check  # numpy, numba, scipy: module docstring
    from core.periodic_orbit import find_orbit
    orbit = find_orbit(params, dt, t_seed)
    return orbit, step_check(orbit)
