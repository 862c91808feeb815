"""One parameter point end to end: integrate, estimate lambda_max, classify.

**A blow-up of an explicit scheme is not a label.** Euler (the paper's) and RK4 leave
their stability region where the model is stiff: on the fast sliding branch of Fig. 7
(ds_y/dt decays at a rate ~2900 > 2/dt) and where s_y grazes 0 from eq. 19's singular
covariance. When they blow up, or drive s_y below 0, ``analyse`` integrates the point
again with the stiff-safe scheme (core.stiff) at the same step and classifies that run,
with the flag ``stiff-fallback``; a run that diverges there too is a divergence of the
equations (``unstable``, attractor ``divergent``).
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from core.batch import simulate_batch
from core.classify import Summary, classify
from core.closure import CLOSURE_TOL, closure_flags, uphill_flags
from core.history import CarriedState
from core.lyapunov import LyapunovEstimate, estimate
from core.params import Params
from core.result_fields import RECORD_KEYS
from core.solve import SolverSettings, Trajectory, simulate


@dataclass(frozen=True, slots=True)
class PointResult:
    """The outcome of one run: its summary, lambda_max and the trajectory it came from."""

    params: Params
    settings: SolverSettings
    summary: Summary
    lyap: LyapunovEstimate | None
    t_blowup: float | None
    runtime_s: float
    trajectory: Trajectory

    def as_record(self) -> dict[str, object]:
        """The flat record the CLI prints with --json and the store keeps: the result
        fields of core.result_fields (their one definition), then the solver's dt and
        t_end, in RECORD_KEYS order. A field listed there must be computed here."""
        s = self.summary
        values = {
            "regime": s.regime,
            "detail": s.detail,
            "lambda_max": self.lyap.value if self.lyap else math.nan,
            "lambda_err": self.lyap.error if self.lyap else math.nan,
            "amplitude": s.amplitude,
            "period": s.period,
            "period_count": s.period_count,
            "maxima_per_period": s.maxima_per_period,
            "attractor": s.attractor,
            "settled": s.settled,
            "flags": ",".join(s.flags),
            "peaks": list(s.peaks),
            "frequency": s.frequency,
            "drift": s.drift,
            "zero_one_k": s.zero_one_k,
            "t_blowup": self.t_blowup,
            "runtime_s": self.runtime_s,
            "dt": self.trajectory.grid.dt,
            "t_end": self.trajectory.grid.t_end,
        }
        return {name: values[name] for name in RECORD_KEYS}


def run_point(p: Params, s: SolverSettings | None = None,
              carried: CarriedState | None = None) -> PointResult:
    """Run one point with settings s (defaults: Euler, dt 1e-3, t_end 1e5, window 1000),
    from the history s.history (``carried``: the state it names, when it names one)."""
    s = s or SolverSettings()
    t0 = time.perf_counter()
    return analyse(simulate(p, s, carried), time.perf_counter() - t0)


def run_batch(points: Sequence[Params], s: SolverSettings | None = None) -> list[PointResult]:
    """Run many points with the same settings through the batched kernels (core.batch).

    Each result's runtime_s is its share of the batch's integration time plus its own
    analysis time."""
    trajectories = simulate_batch(points, s or SolverSettings())
    return [analyse(tr, tr.runtime_s) for tr in trajectories]


def analyse(tr: Trajectory, integration_s: float) -> PointResult:
    """lambda_max and the regime of an integrated trajectory (re-integrated with the
    stiff-safe scheme where an explicit one failed: see the module docstring)."""
    flags: tuple[str, ...] = ()
    t_blowup = tr.t_blowup  # the explicit scheme's, kept beside the flag
    if tr.settings.method != "stiff" and (tr.blew_up or _negative_variance(tr)):
        t1 = time.perf_counter()
        tr = simulate(tr.params, replace(tr.settings, method="stiff", dt=tr.grid.dt), tr.carried)
        integration_s += time.perf_counter() - t1
        flags = ("stiff-fallback",)
    t0 = time.perf_counter()
    s = tr.settings
    lyap = estimate(tr.lyap_logs, tr.grid.renorm_interval) if s.lyap and not tr.blew_up else None
    summary = classify(tr.window_t, tr.window, tr.blew_up, lyap, tr.mid_t, tr.mid, tr.params)
    states = np.concatenate((tr.trace, tr.mid, tr.window), axis=1)
    flags += summary.flags + closure_flags(states) + uphill_flags(states, tr.params.v)
    summary = replace(summary, flags=flags)
    return PointResult(tr.params, s, summary, lyap, t_blowup,
                       integration_s + time.perf_counter() - t0, tr)


def _negative_variance(tr: Trajectory) -> bool:
    """s_y < 0 beyond round-off in a sample: an explicit step overshot the variance's decay
    (the model's own excursions below 0, where the closure breaks down, the stiff scheme
    keeps and flags). Round-off is core.closure's CLOSURE_TOL, so that a run is not
    re-integrated for a sample the closure check accepts (d = 0 keeps eq. 19's singular
    covariance: samples at -4.7e-13). Only samples are seen, the trace's ~2000 points and
    the windows: an excursion between them that leaves the attractor unchanged goes
    unnoticed (d = 0, k = 12, tau = 0.2: Euler's s_y = -1.6e-5 early on is sampled at
    t_end = 500, not at 5000; both runs rest at the fixed point). An excursion that changes
    the attractor persists and is seen (b = 9, tau = 0.2, k = 6: s_y = -2.05)."""
    return any(bool(np.any(a[3] < -CLOSURE_TOL * np.maximum(1.0, np.abs(a[2]) + np.abs(a[3]))))
               for a in (tr.trace, tr.mid, tr.window) if a.shape[1])
