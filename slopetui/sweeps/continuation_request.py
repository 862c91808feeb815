"""A continuation's request checked from text: the one check of ``slopetui continue``'s
flags and of the application's continuation form, each refusal a ParameterError naming
the field (as the CLI names its flag: to, points, max-step) and its range. No UI here;
numpy and numba load only when the spec is built (core.branch_start).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from core.params import PARAM_NAMES, ParameterError, Params
from slopetui.sweeps.orbit_point import check_seed_steps
from slopetui.sweeps.request_fields import number, whole

if TYPE_CHECKING:
    from core.branch_start import BranchSpec

#: Parameters a branch can follow: every parameter of the model but delta, which only
#: places the seed (eq. 19), not the orbit.
CONTINUABLE = tuple(n for n in PARAM_NAMES if n != "delta")

#: The largest max-step: a step along the branch in (parameter, period) space; a larger
#: one is no request a continuation can honour (its steps adapt far below it).
MAX_STEP = 1e3

#: The most points a branch may ask for.
MAX_POINTS = 5000

#: core.periodic_orbit.SEED_T_END (not imported: numpy): a simulated seed's length.
SEED_T_END = 3000.0


def max_step(text: str) -> float:
    allowed = f"a number above 0, at most {MAX_STEP:g}"
    try:
        value = float(text)
    except ValueError:
        raise ParameterError("max-step", text, allowed) from None
    if not (math.isfinite(value) and 0 < value <= MAX_STEP):
        raise ParameterError("max-step", text, allowed)
    return value


def continuation_spec(params: Params, dt: float, param: str, from_hopf: bool, to: str | None,
                      points: str, step: str, hopf_branch: int = 1) -> BranchSpec:
    """The continuation in ``param`` from ``params`` (the ``hopf_branch``-th Hopf point, or
    the orbit a simulation settles on), checked; ParameterError naming the field."""
    if param not in CONTINUABLE:
        raise ParameterError("param", param, f"one of {', '.join(CONTINUABLE)}")
    end = None if to is None else number("to", to, params, param)
    n, largest = whole("points", points, 2, MAX_POINTS), max_step(step)
    here = getattr(params, param)
    # before, a branch from there to there took one step past it and exited 0
    if end is not None and not from_hopf and end == here:
        raise ParameterError("to", to, f"a value other than the start, {param} = {here:g}")
    if not from_hopf:  # a simulated orbit's seed, held in memory
        check_seed_steps(params, dt, SEED_T_END)
    from core.branch_start import BranchSpec  # numpy: module docstring
    return BranchSpec(params, param, dt, from_hopf, end, n, largest, hopf_branch)


def estimate(spec: BranchSpec) -> str:
    """What the continuation will take, as far as it is known before it runs: its points
    and the size of each orbit's state (the time per point depends on Newton's steps,
    which nothing predicts)."""
    state = 2 * round(spec.params.tau / spec.dt)
    start = "the Hopf point" if spec.from_hopf else "a simulated orbit"
    end = "" if spec.end is None else f", until {spec.name} passes {spec.end:g}"
    return (f"from {start} in {spec.name}, at most {spec.max_points} points{end}; each a "
            f"Newton-Krylov solve on a state of {state:,} numbers (2 tau / dt); a worker "
            "saves it point by point")
