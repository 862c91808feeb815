"""lambda_max of a run against the continuous model: what it should be, where theory says.

The kernels' lambda_max is exact for the integrator's map (their tangent is the map's
derivative), not for the delay equations 6a-6e: against those it carries the scheme's
bias, O(dt) for Euler and the stiff scheme, O(dt^4) for RK4. Measured at the paper's
Euler dt = 1e-3 in sliding runs: 0.2-1.7 % of lambda_max, up to 10 sigma of its
statistical error (the block error of core.lyapunov knows nothing of it). Examples:
k = 5, tau = 2: -0.179522(56) (Euler map) against -0.179662 (continuous); k = 12,
tau = 0.2: -3.450042 against -F' = -3.456 (core.stiff's docstring).

Where theory gives the continuous exponent, it is computed here and the bias is the
difference; elsewhere (a chaotic run, a fast branch) it is unknown, and only a second run
at dt / 2 would measure it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from core.methods import REGISTRY
from core.params import Params
from core.stability import leading_exponent


@dataclass(frozen=True)
class ContinuousExponent:
    """The continuous model's lambda_max at a run's attractor and where it comes from."""

    value: float
    source: str  # "linear theory" (the leading root) or "flow direction" (exactly 0)

    def bias(self, measured: float) -> float:
        """measured - continuous: the scheme's bias plus the statistical error."""
        return measured - self.value


def continuous_exponent(p: Params, attractor: str) -> ContinuousExponent | None:
    """The exponent lambda_max estimates, in the continuous model, where theory gives it.

    fixed-point, and unstable-fixed-point (a window that has not departed yet): the leading
    nonzero root of the characteristic function (core.stability.leading_exponent; 2 to
    330 ms a point). periodic or torus: exactly 0,
    the perturbation along the flow neither grows nor decays on a stable orbit or torus.
    None elsewhere (chaotic, fast-branch, variance-state, divergent, unsettled).
    """
    if attractor in ("fixed-point", "unstable-fixed-point"):
        return ContinuousExponent(leading_exponent(p), "linear theory")
    if attractor in ("periodic", "torus"):
        return ContinuousExponent(0.0, "flow direction")
    return None


def relative_bias(measured: float, exact: ContinuousExponent) -> float:
    """|bias| / |exact|, nan when the exact value is 0 (a bias is then absolute only)."""
    if exact.value == 0.0 or not math.isfinite(measured):
        return math.nan
    return abs(exact.bias(measured)) / abs(exact.value)


def bias_note(p: Params, attractor: str, method: str, dt: float, measured: float) -> str:
    """One line beside a lambda_max: which map it belongs to and, where theory gives the
    continuous exponent, the bias against it, e.g. "Euler map at dt = 0.001; continuous
    -0.179662 (linear theory): bias +1.4e-04 (0.078 %), O(dt)"."""
    # the order of the scheme's global error is that of its lambda_max bias
    p_dt = REGISTRY[method].order if method in REGISTRY else 1
    order = "O(dt)" if p_dt == 1 else f"O(dt^{p_dt})"
    head = f"{method} map at dt = {dt:g}"
    exact = continuous_exponent(p, attractor) if math.isfinite(measured) else None
    if exact is None:
        return f"{head}; its {order} bias against the continuous model is not known here " \
               "(a run at dt / 2 measures it)"
    rel = relative_bias(measured, exact)
    share = f" ({100 * rel:.2g} %)" if math.isfinite(rel) else ""
    return (f"{head}; continuous {exact.value:.6g} ({exact.source}): bias "
            f"{exact.bias(measured):+.1e}{share}, {order}")
