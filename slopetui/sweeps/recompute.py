"""Recomputing a stored run, and whether the result agrees with the stored one.

The store keeps each run's summary, not its trajectory (see the run detail screen,
``slopetui.tui.screens.run_detail``, for why). The model is deterministic: a run's
parameters and solver settings integrated again give the trajectory the worker saw (bit
for bit with the same engine on the same machine). This module is that service, free of
any UI: a copy of the run (``StoredRun``), its recomputation (``compute_traces``) and the
tolerance policy that compares the two (``compare``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from typing import TYPE_CHECKING, Any, TypeVar, dataclass_transform

import numpy as np

from core.classify import Summary, power_spectrum
from core.history import CarriedState
from core.lyapunov import LyapunovEstimate, running
from core.lyapunov_bias import bias_note
from core.params import PARAM_NAMES, Params
from core.point import run_point
from core.result_fields import RESULT_FIELDS, Kind
from core.solve import SolverSettings
from slopetui.store.queries import run_by_id
from slopetui.store.runs.initial_states import load_state

if TYPE_CHECKING:
    from slopetui.store.database import Database
    from slopetui.store.models import Run

__all__ = ["LAMBDA_REL_TOL", "LAMBDA_SIGMAS", "MATCH_TEXT", "StoredRun", "Traces", "Verdict",
           "compare", "compute_traces", "lambda_text", "load_run", "recompute"]

MATCH_TEXT = "recomputed: matches the stored result"
#: Two lambda_max values are "the same" within this relative difference (last digits of
#: a sum over ~1e4 renormalisations, which FMA contraction may reorder across machines).
LAMBDA_REL_TOL = 1e-6
#: ... or, failing that, "agree within error" within this many combined standard errors.
LAMBDA_SIGMAS = 3.0

T = TypeVar("T")
#: The Python type of a stored result field of each kind, as a Run attribute gives it.
_ANNOTATIONS: dict[Kind, str] = {"text": "str | None", "measure": "float",
                                 "count": "int | None", "list": "list[float] | None",
                                 "optional": "float | None", "flag": "bool | None",
                                 "pairs": "list[list[float]] | None"}


@dataclass_transform(frozen_default=True)
def _with_result_fields(cls: type[T]) -> type[T]:
    """cls as a frozen dataclass with the result fields of core.result_fields appended
    (their one definition): a field added there is copied here without an edit."""
    cls.__annotations__.update({f.name: _ANNOTATIONS[f.kind] for f in RESULT_FIELDS})
    return dataclass(frozen=True, slots=True)(cls)


@_with_result_fields
class StoredRun:
    """The columns of a Run row that the run detail screen shows, copied out of the
    session: those below, then every result field (core.result_fields).

    Field names are the Run attributes. Measurements are NaN where undefined or not
    computed yet (``Measure``); t_blowup is None when the run did not blow up.
    """

    id: int
    sweep_id: int
    status: str
    a: float
    b: float
    c: float
    d: float
    k: float
    v: float
    tau: float
    delta: float
    method: str
    dt: float
    t_end: float
    window: float
    lyap: bool
    engine: str
    worker_id: str | None
    attempts: int
    error: str | None
    cached_from: int | None
    inferred: bool
    level: int | None
    history: str
    stop: str
    ic: int
    #: The final state the history names (slopetui.store.runs.initial_states), if it names one.
    carried: bytes | None

    if TYPE_CHECKING:  # the result fields, added by _with_result_fields
        def __getattr__(self, name: str) -> Any: ...

    @classmethod
    def of(cls, run: Run, carried: bytes | None = None) -> StoredRun:
        return cls(**{f.name: getattr(run, f.name) for f in fields(cls) if f.name != "carried"},
                   carried=carried)

    @property
    def done(self) -> bool:
        return self.status == "done"

    def inputs(self) -> tuple[Params, SolverSettings]:
        """The run's parameters and solver settings, lambda_max always on (its running
        estimate is one of the plots), the stop rule the run's (a certified run's window
        ends where it stopped). Raises ParameterError for invalid inputs."""
        params = Params(**{n: getattr(self, n) for n in PARAM_NAMES})
        settings = SolverSettings(method=self.method, dt=self.dt, t_end=self.t_end,
                                  window=self.window, lyap=True, history=self.history,
                                  stop=self.stop)
        return params, settings

    def carried_state(self) -> CarriedState | None:
        """The final state the run's history starts from (None: a named history)."""
        return None if self.carried is None else CarriedState.from_bytes(self.carried)


def load_run(db: Database, run_id: int) -> StoredRun | None:
    """The run's copy (with the final state its history names, if any), or None if the
    store has no such run."""
    row = run_by_id(db, run_id)
    if row is None:
        return None
    history = row.history or "constant"
    return StoredRun.of(row, load_state(db, history) if history.startswith("state:") else None)


@dataclass(frozen=True, slots=True)
class Traces:
    """What a recomputation gives the plots, in model units: the analysis window
    (t, m_x, m_y), the spectrum of m_y (frequency in 1/time), the running lambda_max
    (lam_t, lam in 1/time), the recomputed summary, and which map lambda_max belongs to
    with its bias against the continuous model where theory gives it
    (core.lyapunov_bias.bias_note; empty without lambda_max)."""

    t: np.ndarray
    m_x: np.ndarray
    m_y: np.ndarray
    freq: np.ndarray
    power: np.ndarray
    lam_t: np.ndarray
    lam: np.ndarray
    summary: Summary
    lyap: LyapunovEstimate | None
    lambda_note: str = ""


@dataclass(frozen=True, slots=True)
class Verdict:
    """The recomputed result against the stored one: ``ok`` False is a warning."""

    ok: bool
    text: str


def compute_traces(params: Params, settings: SolverSettings,
                   carried: CarriedState | None = None) -> Traces:
    """Integrate the run again (seconds: as long as the run took) from its history
    (``carried``: the state it names, if any) and derive the plots' data."""
    result = run_point(params, settings, carried)
    tr = result.trajectory
    t, m_x, m_y = tr.window_t, tr.window[0], tr.window[1]
    freq, power = power_spectrum(t, m_y)
    lam_t, lam = running(tr.lyap_logs, tr.grid.renorm_interval)
    note = (bias_note(params, result.summary.attractor, result.settings.method, tr.grid.dt,
                      result.lyap.value) if result.lyap else "")
    return Traces(t, m_x, m_y, freq, power, lam_t, lam, result.summary, result.lyap, note)


def recompute(run: StoredRun) -> Traces:
    """The stored run integrated again from its own inputs and history (compute_traces).
    Raises ParameterError for inputs the engine refuses."""
    return compute_traces(*run.inputs(), run.carried_state())


def lambda_text(value: float, error: float) -> str:
    """lambda_max with its error, "–" when there is none."""
    if not math.isfinite(value):
        return "–"
    return f"{value:.3g} ± {error:.2g}" if math.isfinite(error) else f"{value:.3g}"


def _same_lambda(a: float, b: float) -> bool:
    if not (math.isfinite(a) and math.isfinite(b)):
        return not math.isfinite(a) and not math.isfinite(b)
    return abs(a - b) <= LAMBDA_REL_TOL * max(abs(a), abs(b), 1e-12)


def _within_error(a: float, err_a: float, b: float, err_b: float) -> bool:
    sigma = math.hypot(err_a, err_b)
    return math.isfinite(sigma) and abs(a - b) <= LAMBDA_SIGMAS * sigma


def compare(run: StoredRun, traces: Traces, engine_now: str) -> Verdict:
    """The recomputed regime and lambda_max against the stored ones.

    Equal regimes and lambda_max equal to LAMBDA_REL_TOL match; lambda_max within
    LAMBDA_SIGMAS combined errors "agrees within error"; anything else is a warning that
    names the likely cause: an engine changed since the run (``run.engine`` against
    ``engine_now``), or else the machine or library versions.
    """
    s, lyap = traces.summary, traces.lyap
    lam, err = (lyap.value, lyap.error) if lyap else (math.nan, math.nan)
    engine_changed = run.engine != engine_now
    engine_note = (f"the engine changed since the run (stored {run.engine}, now {engine_now})"
                   if engine_changed else "")
    if run.inferred:
        computed = f"computed: {s.regime} ({s.detail}), λmax {lambda_text(lam, err)}"
        if not run.done:
            return Verdict(True, f"{computed} · inferred failed, nothing to compare")
        if s.regime == run.regime:
            return Verdict(True, f"{computed} · the inferred regime was right")
        return Verdict(False, f"warning: {computed}; the inferred regime was {run.regime}")
    if not run.done:
        return Verdict(True, f"computed: {s.regime} ({s.detail}), λmax {lambda_text(lam, err)}"
                             f" · nothing stored to compare ({run.status})")
    # a run stored without lambda_max (lyap off) has nothing to compare it with
    lambda_stored = run.lyap or math.isfinite(run.lambda_max)
    same_regime = s.regime == run.regime
    same_lambda = not lambda_stored or _same_lambda(lam, run.lambda_max)
    if same_regime and same_lambda:
        return Verdict(True, MATCH_TEXT + (f" ({engine_note})" if engine_changed else ""))
    if same_regime and _within_error(lam, err, run.lambda_max, run.lambda_err):
        return Verdict(True, f"{MATCH_TEXT} in regime; λmax {lambda_text(lam, err)} agrees "
                             f"with the stored one within error"
                             + (f" ({engine_note})" if engine_changed else ""))
    why = engine_note or "same engine: another machine or library version?"
    return Verdict(False, f"warning: recomputed {s.regime}, λmax {lambda_text(lam, err)}; "
                          f"stored {run.regime}, λmax "
                          f"{lambda_text(run.lambda_max, run.lambda_err)}; {why}")
