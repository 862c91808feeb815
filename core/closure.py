"""Is the mean-field state a possible state of an ensemble? Checks of a trajectory.

The moments of a real ensemble of blocks obey s_x >= 0, s_y >= 0 and s_x s_y >= u^2 (a
covariance matrix is positive semi-definite). Eqs. 6a-6e do not enforce this: a run that
violates it has left the validity of the mean-field (Gaussian) closure, and its labels
describe the equations, not a slope. eq. 19 starts exactly on the boundary
(s_x s_y = u^2 = delta^2). A block that slides uphill (v + m_y < 0) is allowed by the
equations but not by friction that opposes motion; it is flagged too.
"""

from __future__ import annotations

import numpy as np

#: Violations smaller than this (in the variables' own units, relative to max(1, |s|))
#: are round-off: on the boundary s_x s_y = u^2 where eq. 19 starts, an explicit step
#: leaves s_x s_y - u^2 of either sign at the level of dt^2 delta^2.
CLOSURE_TOL = 1e-9


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
