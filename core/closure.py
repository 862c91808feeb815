"""Is the mean-field state a possible state of an ensemble? Checks of a trajectory.

The moments of a real ensemble of blocks obey s_x >= 0, s_y >= 0 and s_x s_y >= u^2 (a
covariance matrix is positive semi-definite). Eqs. 6a-6e do not enforce this: a run that
violates it has left the validity of the mean-field (Gaussian) closure, and its labels
describe the equations, not a slope. eq. 19 starts exactly on the boundary
(s_x s_y = u^2 = delta^2). A block that slides uphill (v + m_y < 0) is allowed by the
equations but not by friction that opposes motion; it is flagged too.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: Violations smaller than this (in the variables' own units, relative to max(1, |s|))
#: are round-off: on the boundary s_x s_y = u^2 where eq. 19 starts, an explicit step
#: leaves s_x s_y - u^2 of either sign at the level of dt^2 delta^2.
CLOSURE_TOL = 1e-9


#: A state along the trajectory violates realisability when s_x, s_y or s_x s_y - u^2 is
#: below -REALISABLE_TOL: CLOSURE_TOL at its smallest scale (1), absolute, so that any
#: sample closure_flags rejects is a violation here too, and a kernel tests a step with
#: three comparisons (core.recording.lowest). Round-off stays far below it: eq. 19 starts
#: at s_x s_y - u^2 = delta^2 - delta^2 = 0, and the stiff scheme, which keeps the
#: covariance positive semidefinite in exact arithmetic, had running minima of 0 and above
#: (1e-279 to 1e-300) for s_x, s_y and s_x s_y - u^2 over every step at d = 0 (k = 12,
#: tau = 10; k = 5, tau = 2; k = 12, tau = 0.2; t <= 200), where the exact covariance stays
#: singular. The one negative value round-off gave was s_x s_y - u^2 = -8.3e-19 at t = 0
#: (delta = 0.1: delta^2 less its rounding in the fused multiply-add); it scales as
#: delta^2, so a delta beyond ~1e3 would need a relative test. What exceeds it is the
#: scheme's: eqs. 6c-6e are the Lyapunov equation dS/dt = A S + S A^T + D (core.stiff),
#: which keeps the exact covariance positive semidefinite whatever G(t) does. RK4 at
#: dt = 1e-2 left s_x s_y - u^2 = -3.7e-8 on those d = 0 runs (its truncation error);
#: Euler at dt = 1e-3 drives s_y to -1.1e-3 at t = 0.07 at the defaults.
REALISABLE_TOL = 1e-9


@dataclass(frozen=True, slots=True)
class Realisability:
    """Whether every step of a run was a possible covariance: the running minima of s_x,
    s_y and s_x s_y - u^2 over the whole trajectory (every step, kept inside the kernels),
    and the time of the first step any of them fell below -REALISABLE_TOL (None: none
    did)."""

    min_s_x: float
    min_s_y: float
    min_det: float
    t_first: float | None

    @property
    def realisable(self) -> bool:
        return self.t_first is None

    def flags(self) -> tuple[str, ...]:
        """``unrealisable`` if some step left the possible covariances."""
        return () if self.realisable else ("unrealisable",)

    def text(self) -> str:
        """The minima, and when the first violation was, in one line."""
        lows = (f"min s_x {_g(self.min_s_x)}, s_y {_g(self.min_s_y)}, "
                f"s_x s_y - u^2 {_g(self.min_det)}")
        if self.t_first is None:
            return f"realisable at every step ({lows})"
        return f"{UNREALISABLE_FROM}{self.t_first:.6g} ({lows})"


#: How the detail of an unrealisable run (core.point) appends its text, after "; ".
UNREALISABLE_FROM = "unrealisable from t = "


def classifier_detail(detail: str) -> str:
    """A run's detail without the realisability clause core.point appends: the
    classifier's words alone, which the report counts by kind (its minima differ from
    run to run)."""
    return detail.split(f"; {UNREALISABLE_FROM}", 1)[0]


def _g(x: float) -> str:
    return f"{x:.3g}" if math.isfinite(x) else str(x)


def closure_flags(states: np.ndarray) -> tuple[str, ...]:
    """``closure-breakdown`` if the samples (rows m_x, m_y, s_x, s_y, u) leave the set of
    possible covariances."""
    if states.shape[1] == 0:
        return ()
    s_x, s_y, u = states[2], states[3], states[4]
    scale = np.maximum(1.0, np.abs(s_x) + np.abs(s_y))
    bad = ((s_x < -CLOSURE_TOL * scale) | (s_y < -CLOSURE_TOL * scale)
           | (s_x * s_y - u * u < -CLOSURE_TOL * scale * scale))
    return ("closure-breakdown",) if bool(np.any(bad)) else ()


def uphill_flags(states: np.ndarray, v: float) -> tuple[str, ...]:
    """``uphill`` if the mean velocity v + m_y of some sample is negative."""
    if states.shape[1] == 0:
        return ()
    return ("uphill",) if bool(np.any(v + states[1] < 0.0)) else ()
