"""A hysteresis sweep's request checked from text: the one check of ``slopetui
hysteresis``'s flags and of the application's hysteresis form, each refusal a
ParameterError naming the field (as the CLI names its flag: from, to, points, t-settle,
window, tol) and its range. No UI here; numpy and numba load only when it checks
(core.hysteresis's defaults, core.solve's limits), never when imported.
"""

from __future__ import annotations

import math

from core.params import ParameterError, Params
from slopetui.queue.hysteresis_jobs import TOL_MAX, HysteresisSpec
from slopetui.sweeps.request_fields import number, whole

#: Bytes a step of the window takes: core.hysteresis.settle keeps the window's five rows
#: of float64, every step.
WINDOW_STEP_BYTES = 5 * 8

#: The most values each way.
MAX_POINTS = 2000


def hysteresis_spec(params: Params, dt: float, param: str, start_text: str, stop_text: str,
                    points: str, t_settle_text: str | None = None,
                    window_text: str | None = None, tol_text: str | None = None
                    ) -> HysteresisSpec:
    """The sweep of ``param`` from ``start_text`` to ``stop_text`` and back, checked; None
    for t-settle, window and tol: core.hysteresis's defaults."""
    from core.hysteresis import T_SETTLE, TOL, WINDOW  # numba: module docstring
    from core.solve import MAX_RUN_BYTES, MAX_STEPS

    start = number("from", start_text, params, param)
    stop = number("to", stop_text, params, param)
    if start == stop:
        raise ParameterError("to", stop_text, f"a value other than from = {start:g}")
    n = whole("points", points, 2, MAX_POINTS)
    t_settle = T_SETTLE if t_settle_text is None else number("t-settle", t_settle_text)
    window = min(WINDOW, t_settle) if window_text is None else number("window", window_text)
    if not (math.isfinite(t_settle) and t_settle >= 10 * params.tau and t_settle <= 1e6):
        raise ParameterError("t-settle", t_settle, f"a number from 10 tau = {10 * params.tau:g} "
                                                   "to 1e6")
    if t_settle / dt > MAX_STEPS:  # a run's limit (core.solve), per point
        raise ParameterError("t-settle", t_settle, f"at most {MAX_STEPS:.0e} steps of dt = "
                                                   f"{dt:g}, {MAX_STEPS * dt:g}")
    if not (math.isfinite(window) and 10 * dt <= window <= t_settle):
        raise ParameterError("window", window, f"a number from 10 dt to t-settle = {t_settle:g}")
    if window / dt * WINDOW_STEP_BYTES > MAX_RUN_BYTES:  # held in memory, as a run's
        high = MAX_RUN_BYTES / WINDOW_STEP_BYTES * dt
        raise ParameterError("window", window, f"at most {high:g} ({MAX_RUN_BYTES / 1024**3:g} "
                                               f"GiB of samples at dt = {dt:g})")
    tol = TOL if tol_text is None else number("tol", tol_text)
    if not 0.0 < tol < TOL_MAX:
        raise ParameterError("tol", tol, f"a number above 0 and below {TOL_MAX:g}")
    return HysteresisSpec(params, param, start, stop, n, dt, t_settle, window, tol)


def estimate(spec: HysteresisSpec) -> str:
    """The RK4 steps the sweep takes on its grid (each point integrates t_settle, up and
    down), before the bisections that refine each transition."""
    steps = 2 * spec.n_points * spec.t_settle / spec.dt
    return (f"{2 * spec.n_points} points (up and down), {steps:.3g} RK4 steps of dt = "
            f"{spec.dt:g}, then a bisection per transition to {spec.tol:g}; a worker saves it "
            "point by point")
