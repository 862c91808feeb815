"""The four analyses the application starts (slopetui.tui.screens.analysis_form): what
each form asks, and which shared service checks and starts it. Each opens at a point (the
diagram cursor's, a run's, else the paper's defaults), which the form shows and may change.

The checks are the CLI's own (``slopetui continue``, ``hysteresis``, ``orbit``), so a
field is refused here exactly when its flag is refused there, in the same words.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from core.params import PARAM_NAMES, Params
from slopetui.sweeps import certified_rerun, continuation_request, hysteresis_request, orbit_point
from slopetui.sweeps.branches import submit as submit_branch
from slopetui.sweeps.hysteresis_runs import submit as submit_hysteresis
from slopetui.tui.screens.analysis_form import Analysis, Checked, Field

if TYPE_CHECKING:
    from core.branch_start import BranchSpec
    from core.orbit_step import StepCheck
    from core.periodic_orbit import Orbit
    from slopetui.queue.hysteresis_jobs import HysteresisSpec
    from slopetui.store.database import Database

#: Parameters a hysteresis sweep can follow: not tau (the state's history is one delay
#: long and would change size) nor delta (which only places the first point's start);
#: slopetui.cli.arguments.hysteresis.FOLLOWABLE.
FOLLOWABLE = tuple(n for n in PARAM_NAMES if n not in ("tau", "delta"))

#: The orbit's RK4 step and seed length (`slopetui orbit`'s defaults).
ORBIT_DT, T_SEED = "0.01", "3000"

#: Multipliers the orbit's result lists (the leading ones, by modulus: `slopetui orbit`).
SHOWN = 6


def _g(value: float) -> str:
    return f"{value:.6g}"


def _point_rows(at: Params) -> tuple[tuple[Field, ...], ...]:
    """The eight parameters in two rows, filled from ``at``."""
    return tuple(tuple(Field(n, n, _g(getattr(at, n))) for n in names)
                 for names in (("a", "b", "c", "d"), ("k", "v", "tau", "delta")))


def _point(values: dict[str, str]) -> tuple[Params, float]:
    return orbit_point.point_of(values)


# --- a continuation -----------------------------------------------------------------------

def _check_continuation(values: dict[str, str]) -> Checked:
    params, dt = _point(values)
    spec = continuation_request.continuation_spec(
        params, dt, values["param"], values["start"] == "hopf", values["to"] or None,
        values["points"], values["max-step"])
    return Checked(spec, continuation_request.estimate(spec))


def _start_continuation(db: Database, spec: BranchSpec) -> str:
    cid = submit_branch(db, spec)
    return f"continuation {cid} queued: the pool computes it; the Branches screen (4) shows it"


def continuation(at: Params, param: str = "k") -> Analysis:
    """A continuation of orbits in ``param`` from ``at`` (`slopetui continue --submit`)."""
    return Analysis(
        title="Continuation of periodic orbits",
        rows=((Field("param", "param", param, continuation_request.CONTINUABLE),
               Field("start", "from", "hopf", ("hopf", "orbit")),
               Field("to", "to", "", placeholder="(none)"),
               Field("points", "points", "300")),
              *_point_rows(at),
              (Field("dt", "dt", ORBIT_DT), Field("max-step", "max-step", "0.5"))),
        check=_check_continuation, start=_start_continuation,
        note="from hopf: the Hopf point of the steady state in param; from orbit: the "
             "orbit a simulation at this point settles on. slopetui continue takes the same.")


# --- a hysteresis sweep -------------------------------------------------------------------

def _check_hysteresis(values: dict[str, str]) -> Checked:
    params, dt = _point(values)
    spec = hysteresis_request.hysteresis_spec(
        params, dt, values["param"], values["from"], values["to"], values["points"],
        values["t-settle"] or None, values["window"] or None, values["tol"] or None)
    return Checked(spec, hysteresis_request.estimate(spec))


def _start_hysteresis(db: Database, spec: HysteresisSpec) -> str:
    sid = submit_hysteresis(db, spec)
    return f"hysteresis sweep {sid} queued: the pool computes it; the Branches screen (4) shows it"


def hysteresis(at: Params, param: str = "k") -> Analysis:
    """A warm-started sweep of ``param`` up and down around ``at`` (`slopetui hysteresis
    --submit`); it opens on the point's value +- 20 %."""
    here = getattr(at, param)
    return Analysis(
        title="Hysteresis sweep",
        rows=((Field("param", "param", param, FOLLOWABLE),
               Field("from", "from", _g(0.8 * here)), Field("to", "to", _g(1.2 * here)),
               Field("points", "points", "21")),
              *_point_rows(at),
              (Field("dt", "dt", ORBIT_DT),
               Field("t-settle", "t-settle", "", placeholder="6000"),
               Field("window", "window", "", placeholder="1000"),
               Field("tol", "tol", "", placeholder="0.001"))),
        check=_check_hysteresis, start=_start_hysteresis,
        note="Each point starts from the one before's final state: up, then down. "
             "slopetui hysteresis takes the same.")


# --- an orbit -----------------------------------------------------------------------------

def _check_orbit(values: dict[str, str]) -> Checked:
    params, dt = _point(values)
    t_seed = orbit_point.seed_length(values["t-seed"], params, dt)
    steps = orbit_point.seed_steps(params, dt, t_seed)
    return Checked((params, dt, t_seed),
                   f"a seed simulation of {steps:.3g} RK4 steps, then Newton-Krylov shooting on "
                   f"a state of {2 * round(params.tau / dt):,} numbers (2 tau / dt)")


def orbit_text(o: Orbit, check: StepCheck) -> str:
    """The orbit's period, amplitude, step check and leading multipliers, as `slopetui
    orbit` says them."""
    from core.classify import maxima_words  # numpy: loaded once an orbit is computed
    m = o.multipliers
    lines = [f"period {o.period:.8g}, amplitude {o.amplitude:.5g} (peak to peak of m_y), "
             f"{'stable' if o.stable else 'unstable'} ({m.unstable_count} multipliers outside "
             "the unit circle)",
             f"step check {check.text(maxima_words(check.maxima_per_period) + ' a period')}",
             f"Newton: {o.newton_steps} steps, residual {o.residual:.1e}; multipliers (* the "
             "flow's):"]
    for i, v in enumerate(m.values[:SHOWN]):
        mark = "*" if i == m.flow_index else " "
        lines.append(f" {mark} {v.real:+.6f} {v.imag:+.6f}i  |mu| = {abs(v):.6f}")
    return "\n".join(lines)


def _start_orbit(_db: Database, request: tuple[Params, float, float]) -> str:
    from core.orbit import OrbitError  # numpy: loaded once an orbit is computed
    try:
        return orbit_text(*orbit_point.compute_orbit(*request))
    except OrbitError as exc:
        return f"no orbit: {exc}"


def orbit(at: Params) -> Analysis:
    """The periodic orbit at ``at`` (`slopetui orbit`), computed here in the background."""
    return Analysis(
        title="Periodic orbit at a point",
        rows=(*_point_rows(at), (Field("dt", "dt", ORBIT_DT), Field("t-seed", "t-seed", T_SEED))),
        check=_check_orbit, start=_start_orbit, verb="Compute", closes=False,
        note="Simulated from eq. 19, corrected by shooting; its Floquet multipliers against "
             "the unit circle. slopetui orbit takes the same.")


# --- a certified re-run -------------------------------------------------------------------

def _check_rerun(db: Database | None) -> Any:
    def check(values: dict[str, str]) -> Checked:
        from slopetui.sweeps.spec import SpecError
        try:
            run_id = int(values["run"])
        except ValueError:
            raise SpecError("run", f"{values['run']!r} is not a run id") from None
        if db is None:
            raise SpecError("run", "the store is not open yet")
        spec = certified_rerun.rerun_spec(db, run_id)
        return Checked(run_id, f"one run at t_end = {spec.solver.t_end:g} at most, "
                               f"{spec.solver.method} dt = {spec.solver.dt:g}; it stops where "
                               "its attractor is certified")
    return check


def _start_rerun(db: Database, run_id: int) -> str:
    out = certified_rerun.rerun_certified(db, run_id)
    cached = " (from the cache: an identical run was computed)" if out.n_cached else ""
    return f"sweep {out.sweep_id}: run {run_id} queued again with stop = certified{cached}"


def rerun(db: Database | None, run_id: int) -> Analysis:
    """Run ``run_id`` again with the certified stop, as a one-run sweep."""
    return Analysis(
        title="Certified re-run of a run",
        rows=((Field("run", "run", str(run_id)),),),
        check=_check_rerun(db), start=_start_rerun,
        note="A one-run sweep at the run's point, solver and history, with stop = certified "
             "(the run ends once its attractor is certified), as slopetui submit would queue it.")
