"""Whether an orbit is resolved at its step: the same orbit corrected again at dt / 2.

An orbit of core.periodic_orbit is the RK4 map's at dt (default 0.01): on smooth orbits its
period is accurate to ~1e-9 against finer steps, but not where the slips are sharp. At
b = 24, k = 12, tau = 7.43 the orbit at dt 0.01 has amplitude 10.2022 and 13 maxima a
period; at dt 0.005 and 0.0025 9.77107 and one, its period 9.1995183 against 9.2035417
and 9.2035377 (the flow multiplier 7.7e-5 from 1 at 0.01, 3.2e-6 at 0.0025). So the orbit
is corrected again at dt / 2, from its own state on the finer grid, and the changes of its
period, amplitude and maxima say whether its step resolves it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from core.accuracy import TOLERANCE
from core.multiplier_crossing import halved
from core.orbit import OrbitError, PeriodMap
from core.periodic_orbit import Orbit, maxima_in
from core.shooting import correct


@dataclass(frozen=True)
class StepCheck:
    """The orbit at ``dt`` (half its step): its period, amplitude and maxima a period, and
    the orbit's relative changes against it (signed: positive when the orbit's value is
    the larger). ``resolved``: the maxima agree and both changes are within TOLERANCE
    (core.accuracy's 1 %, the threshold that flags a run dt-sensitive); ``reason`` says
    why not, or that Newton failed at dt (then the figures are NaN)."""

    dt: float
    period: float
    amplitude: float
    maxima_per_period: int
    period_change: float
    amplitude_change: float
    resolved: bool
    reason: str = ""

    def record(self) -> dict[str, object]:
        """The JSON object (``step_check``)."""
        return {"dt": self.dt, "period": self.period, "amplitude": self.amplitude,
                "maxima_per_period": self.maxima_per_period,
                "period_change": self.period_change,
                "amplitude_change": self.amplitude_change, "resolved": self.resolved,
                "reason": self.reason}

    def text(self, words: str) -> str:
        """One line: the figures at dt / 2 (``words``: its maxima said), then the verdict."""
        if not math.isfinite(self.period):
            return f"at dt {self.dt:g}: {self.reason}"
        said = (f"at dt {self.dt:g}: period {self.period:.10g} ({self.period_change:+.1e}), "
                f"amplitude {self.amplitude:.6g} ({self.amplitude_change:+.1e}), {words}")
        return f"{said}: resolved" if self.resolved else f"{said}: {self.reason}"


def step_check(o: Orbit) -> StepCheck:
    """``o`` corrected again at half its step (module docstring)."""
    z, g = halved(o.z, o.grid)
    pm = PeriodMap(o.params, g)
    try:
        shot = pm.shoot(z, o.period)
        sol = correct(pm, z, o.period, z, shot.d_dT)
    except OrbitError as exc:
        return StepCheck(g.dt, math.nan, math.nan, 0, math.nan, math.nan, False,
                         f"no orbit near it at half the step ({exc}): not resolved at "
                         f"dt {o.grid.dt:g}")
    m_y = sol.shot.traj[1, g.n_delay:sol.shot.col + 1]
    amplitude = float(m_y.max() - m_y.min())
    maxima = maxima_in(m_y)
    d_period = o.period / sol.period - 1.0
    d_amplitude = o.amplitude / amplitude - 1.0
    far = [f"{name} changes by {abs(v):.1e}" for name, v in (("period", d_period),
                                                             ("amplitude", d_amplitude))
           if abs(v) > TOLERANCE]
    if maxima != o.maxima_per_period:
        far.append(f"{o.maxima_per_period} maxima a period become {maxima}")
    reason = (f"not resolved at dt {o.grid.dt:g} ({', '.join(far)}): take a smaller dt"
              if far else "")
    return StepCheck(g.dt, sol.period, amplitude, maxima, d_period, d_amplitude, not far,
                     reason)
