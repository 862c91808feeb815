"""One parameter point end to end: integrate, estimate lambda_max, classify.

**A blow-up of an explicit scheme is not a label.** Euler (the paper's) and RK4 leave
their stability region where the model is stiff: on the fast sliding branch of Fig. 7
(ds_y/dt decays at a rate ~2900 > 2/dt) and where s_y grazes 0 from eq. 19's singular
covariance. When they blow up, or drive s_y below 0, ``analyse`` integrates the point
again with the stiff-safe scheme (core.stiff) at the same step and classifies that run,
with the flag ``stiff-fallback``; a run that diverges there too is a divergence of the
equations (``unstable``, attractor ``divergent``).

**Realisability along the whole run.** The kernels keep the running minima of s_x, s_y
and s_x s_y - u^2 over every step (core.closure.Realisability); a run whose covariance
left the positive semidefinite ones at some step carries the flag ``unrealisable``, and
its detail says from when and how far. eqs. 6c-6e keep the exact covariance positive
semidefinite, so a violation is the scheme's: Euler at dt = 1e-3 leaves it right after
eq. 19's singular start for delta >= 0.01 (36 of 36 points, none at delta = 1e-6:
docs/numerics.md), RK4 at dt = 1e-2 only where the start is violent (delta = 1).
``closure-breakdown`` says the same of a sample the labels rest on; the stiff fallback
still follows the samples (``_negative_variance``).

**The accuracy of every run.** After the classification a short shadow integration from
the run's final state at dt and dt / 2 estimates the scheme's error at its step
(core.accuracy: ``dt_error``); a run whose amplitude, period or label would change by more
than 1 % carries the flag ``dt-sensitive``. The detail stays the classifier's (the report
counts its words by kind: core.closure.classifier_detail); ``dt_error`` says how much.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, replace

import numpy as np

from core.accuracy import DtError, dt_error
from core.batch import simulate_batch
from core.certified_stop import Stopped, certified_batch, certified_lambda, simulate_to_certificate
from core.certify import NOT_ATTEMPTED, Certificate, certify, relabel
from core.classify import Summary, classify
from core.closure import CLOSURE_TOL, closure_flags, uphill_flags
from core.history import CarriedState
from core.lyapunov import LyapunovEstimate, estimate
from core.params import Params
from core.result_fields import RECORD_KEYS
from core.solve import SolverSettings, Trajectory, moved_into, simulate
from core.spectrum import Spectrum, check_spectrum
from core.spectrum import spectrum as top_exponents

#: The checks over a run's samples (the closure, uphill and negative-variance flags) are
#: "some sample is bad": they are computed on blocks of this many samples, so that their
#: temporaries are a block's (~0.5 MiB an array), not a window's. On the window of 1e5 at
#: dt 1e-3 (2 x 1 041 667 samples), concatenating the samples for the flags took 131 MiB
#: at the peak (tracemalloc), more than the run's own 96 MiB of samples.
SAMPLE_BLOCK = 1 << 16


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
    #: The top Lyapunov exponents (run --spectrum N, core.spectrum); None: not computed.
    spectrum: Spectrum | None = None
    #: The attractor's certificate (core.certify), tried after the window's label.
    certificate: Certificate = NOT_ATTEMPTED
    #: The scheme's error at its step (core.accuracy); None: not estimated.
    accuracy: DtError | None = None
    #: Where lambda_max comes from when not from the run's tangent (a run stopped at its
    #: certificate: core.certified_stop.certified_lambda's words, also in the
    #: certificate's text); empty: the run's own map, whose bias core.lyapunov_bias states.
    lambda_note: str = ""

    def as_record(self) -> dict[str, object]:
        """The flat record the CLI prints with --json and the store keeps: the result
        fields of core.result_fields (their one definition), then the solver's dt, t_end
        and stop rule, in RECORD_KEYS order. A field listed there must be computed here."""
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
            "t_stop": self.trajectory.t_done,
            "certified": self.certificate.certified,
            "certificate": self.certificate.text,
            "multipliers": self.certificate.pairs,
            "slips": self.certificate.certified_slips,
            "dt_error": self.accuracy.value if self.accuracy else math.nan,
            "spectrum": list(self.spectrum.values) if self.spectrum else [],
            "spectrum_err": list(self.spectrum.errors) if self.spectrum else [],
            "dt": self.trajectory.grid.dt,
            "t_end": self.trajectory.grid.t_end,
            "stop": self.settings.stop,
        }
        return {name: values[name] for name in RECORD_KEYS}


def run_point(p: Params, s: SolverSettings | None = None,
              carried: CarriedState | None = None, spectrum: int = 0) -> PointResult:
    """Run one point with settings s (defaults: Euler, dt 1e-3, t_end 1e5, window 1000),
    from the history s.history (``carried``: the state it names, when it names one);
    ``spectrum`` > 0: also its top ``spectrum`` Lyapunov exponents (core.spectrum, a
    second pass of the same scheme), which the classifier takes as its evidence.
    s.stop = "certified": the run stops where its attractor is certified, and its
    lambda_max is then the certificate's (core.certified_stop)."""
    s = s or SolverSettings()
    if spectrum:
        check_spectrum(p, s, spectrum)  # before the run: a refusal costs nothing
    t0 = time.perf_counter()
    found = None
    if s.stop == "certified":
        stopped = simulate_to_certificate(p, s, carried)
        tr, found = stopped.trajectory, stopped.certificate
    else:
        tr = simulate(p, s, carried)
    exponents = top_exponents(p, s, spectrum, carried) if spectrum else None
    return analyse(tr, time.perf_counter() - t0, spectrum=exponents, certificate=found,
                   found_on=stopped.summary if s.stop == "certified" else None)


def run_batch(points: Sequence[Params], s: SolverSettings | None = None) -> list[PointResult]:
    """Run many points with the same settings through the batched kernels (core.batch).

    Each result's runtime_s is its share of the batch's integration time plus its own
    analysis time. A lane re-integrated by the stiff scheme is written over the lane's own
    samples (the trajectories are held nowhere else), so that the batch's memory stays
    what its runs lay out (core.solve.memory_of) with one run's more at a time: the stiff
    run before it is copied, or a lane's analysis.

    Under ``stop = "certified"`` the lanes stop where their runs' attractors are certified
    (core.certified_stop.certified_batch: each run simulate_to_certificate's), and a stopped
    lane's result keeps the certificate that stopped it (analyse). Runs from a carried
    history, which the lanes do not start from, go one by one (run_point). Measured at
    tau = 10, t_end 1e5, Euler with lambda_max (benchmarks/bench_certified_batch.py, CPU,
    in turns, a shared machine): 32 points over k 0.5-25 took 8.4 s on the certifying
    lanes, 11.1 s on the lanes to t_end and 11.4 s one by one (the 11 multi-slip runs at
    k >= 17, which no chunk certifies, run to t_end on the lanes); 8 points (k 2-20, one
    of them never certified) 1.9 s, 3.2 s and 1.6 s."""
    s = s or SolverSettings()
    if s.stop == "certified" and s.history != "constant":
        return [run_point(p, s) for p in points]
    runs = (certified_batch(points, s) if s.stop == "certified"
            else [Stopped(tr) for tr in simulate_batch(points, s)])
    runs.reverse()
    results = []
    while runs:  # each let go once analysed: a re-integrated lane's own window times
        run = runs.pop()  # (16 MiB at window 1e5) are freed, not held to the end
        tr = run.trajectory
        results.append(analyse(tr, tr.runtime_s, overwrite=True, certificate=run.certificate,
                               found_on=run.summary))
    return results


def analyse(tr: Trajectory, integration_s: float, overwrite: bool = False,
            spectrum: Spectrum | None = None, certificate: Certificate | None = None,
            found_on: Summary | None = None) -> PointResult:
    """lambda_max and the regime of an integrated trajectory (re-integrated with the
    stiff-safe scheme where an explicit one failed: see the module docstring).

    overwrite: write that re-integration over tr's own arrays (Trajectory.buffers), as
    run_batch does: a batch's lane views the batch's arrays, which stay alive as long as
    any lane does, so a re-integration in arrays of its own held the lane's samples twice
    (at window 1e5, 8 lanes took 1.30 times what they lay out, 32 lanes 1.60: more lanes,
    more re-integrated). Only for a caller that holds tr nowhere else: tr's samples then
    show the re-integration's. spectrum: the run's top exponents (core.spectrum), dropped
    with a note when the run is re-integrated (they belong to the explicit scheme).
    certificate: the one that stopped tr early (core.certified_stop), found on this same
    window: kept rather than tried again, and lambda_max is then its value (dropped with
    the rest if tr is re-integrated). found_on: the summary of that window the certificate
    was tried on (classify's, with the same arguments: kept rather than computed again;
    at the paper's window a classification took 31 ms at tau = 15, 175 of them 5.5 s of
    CPU in a cProfile of a 40-point certified row)."""
    flags: tuple[str, ...] = ()
    dropped = ""
    t_blowup = tr.t_blowup  # the explicit scheme's, kept beside the flag
    if tr.settings.method != "stiff" and (tr.blew_up or _negative_variance(tr)):
        t1 = time.perf_counter()
        stiff = simulate(tr.params, replace(tr.settings, method="stiff", dt=tr.grid.dt), tr.carried)
        tr = moved_into(stiff, tr.buffers) if overwrite and tr.buffers is not None else stiff
        del stiff  # its own arrays, once copied: freed before the analysis's temporaries
        integration_s += time.perf_counter() - t1
        flags = ("stiff-fallback",)
        if spectrum is not None:
            dropped = "; spectrum dropped: it is the failed explicit scheme's"
        spectrum = None
        certificate = found_on = None
    t0 = time.perf_counter()
    s = tr.settings
    lyap = estimate(tr.lyap_logs, tr.grid.renorm_interval) if s.lyap and not tr.blew_up else None
    if found_on is not None and spectrum is None and not tr.blew_up:
        summary = found_on
    else:
        summary = classify(tr.window_t, tr.window, tr.blew_up, lyap, tr.mid_t, tr.mid,
                           tr.params, spectrum=spectrum)
    summary = replace(summary, detail=summary.detail + dropped)
    flags += summary.flags + _sample_flags(tr)
    real = tr.realisability
    if real is not None and not real.realisable:
        summary = replace(summary, detail=f"{summary.detail}; {real.text()}")
        flags += real.flags()
    accuracy = dt_error(tr, summary)
    if accuracy.sensitive:
        flags += ("dt-sensitive",)
    summary = replace(summary, flags=flags)
    # the labels then follow a certified orbit (core.certify)
    cert = certify(tr, summary) if certificate is None else certificate
    from_certificate = (certified_lambda(tr.params, cert)
                        if certificate is not None and s.lyap else None)
    lambda_note = ""
    if from_certificate is not None:  # a run stopped at its certificate: its lambda_max
        lyap, lambda_note = from_certificate
        cert = replace(cert, text=f"{cert.text}; {lambda_note}")
    summary = relabel(summary, cert, tr.params)
    if cert.scheme_off and "dt-sensitive" not in summary.flags:
        summary = replace(summary, flags=(*summary.flags, "dt-sensitive"))
    return PointResult(tr.params, s, summary, lyap, t_blowup,
                       integration_s + time.perf_counter() - t0, tr, spectrum=spectrum,
                       certificate=cert, accuracy=accuracy, lambda_note=lambda_note)


def _negative_variance(tr: Trajectory) -> bool:
    """s_y < 0 beyond round-off in a sample: an explicit step overshot the variance's decay
    (the exact covariance never leaves the positive semidefinite ones: core.closure; a
    violation at any step is flagged ``unrealisable``). Round-off is core.closure's CLOSURE_TOL, so that a run is not
    re-integrated for a sample the closure check accepts (d = 0 keeps eq. 19's singular
    covariance: samples at -4.7e-13). Only samples are seen, the trace's ~2000 points and
    the windows: an excursion between them that leaves the attractor unchanged goes
    unnoticed (d = 0, k = 12, tau = 0.2: Euler's s_y = -1.6e-5 early on is sampled at
    t_end = 500, not at 5000; both runs rest at the fixed point). An excursion that changes
    the attractor persists and is seen (b = 9, tau = 0.2, k = 6: s_y = -2.05)."""
    return any(bool(np.any(a[3] < -CLOSURE_TOL * np.maximum(1.0, np.abs(a[2]) + np.abs(a[3]))))
               for a in _sample_blocks(tr))


def _sample_blocks(tr: Trajectory) -> Iterator[np.ndarray]:
    """The trace's, the middle window's and the window's samples, SAMPLE_BLOCK at a time
    (views, none empty)."""
    for a in (tr.trace, tr.mid, tr.window):
        for i in range(0, a.shape[1], SAMPLE_BLOCK):
            yield a[:, i:i + SAMPLE_BLOCK]


def _sample_flags(tr: Trajectory) -> tuple[str, ...]:
    """core.closure's flags over every sample of the run (trace, middle window, window):
    each check's flag if a block raises it, as the check over all samples at once."""
    checks: tuple[Callable[[np.ndarray], tuple[str, ...]], ...] = (
        closure_flags, lambda states: uphill_flags(states, tr.params.v))
    flags: tuple[str, ...] = ()
    for check in checks:
        flags += next((f for f in map(check, _sample_blocks(tr)) if f), ())
    return flags
