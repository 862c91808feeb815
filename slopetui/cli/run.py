"""``slopetui run``: integrate and classify one parameter point."""

from __future__ import annotations

import argparse
import math
import sys
from dataclasses import replace
from typing import TYPE_CHECKING, Any

from core import jit_cache
from core.classify import maxima_words
from core.lyapunov_bias import bias_note
from core.params import PARAM_NAMES, ParameterError, Params, friction_warnings
from core.point import run_point
from core.result_fields import JSON_KEYS as RECORD_JSON_KEYS
from core.solve import SolverSettings, validate_run
from core.spectrum import check_count, check_spectrum
from slopetui.cli.options import open_db
from slopetui.json_text import json_text as strict_json
from slopetui.provenance import computed_at
from slopetui.sweeps.carried import final_state_of, parse_history

if TYPE_CHECKING:  # core.point loads numba and the kernels: only `run` itself needs them;
    # core.solve and core.lyapunov_bias load numpy (~0.1 s), which no parser needs
    from core.history import CarriedState
    from core.point import PointResult
    from core.solve import SolverSettings

#: The keys of ``--json``, in order: the documented contract (regime, lambda_max,
#: lambda_err, amplitude, period, peaks, drift, t_blowup, runtime_s), then the rest of the
#: record (derived from core.result_fields, which defines the result once).
JSON_KEYS = RECORD_JSON_KEYS


def parse_inputs(args: argparse.Namespace) -> tuple[Params, SolverSettings]:
    """Build validated Params and SolverSettings from the flags; raises ParameterError.
    A history run:ID is checked for its form here and resolved by ``carried_of``."""
    given = {n: getattr(args, n) for n in PARAM_NAMES if getattr(args, n) is not None}
    params = Params(**given)  # strings are checked and coerced
    name, _ = parse_history(getattr(args, "history", "constant"))
    settings = SolverSettings(method=args.method, dt=args.dt, t_end=args.t_end,
                              window=args.window, lyap=args.lyap,
                              history="constant" if name == "run" else name,
                              stop=getattr(args, "stop", "t_end"))
    validate_run(params, settings)  # the pair: dt against tau, the engine's limits, the window
    return params, settings


def spectrum_count(args: argparse.Namespace, params: Params, settings: SolverSettings) -> int:
    """N of --spectrum (0: none), checked against the run; raises ParameterError."""
    given = getattr(args, "spectrum", "0")
    if str(given).strip() == "0":
        return 0
    n = check_count(given)
    if settings.stop == "certified":  # the tangents integrate to t_end (core.spectrum)
        raise ParameterError("spectrum", given, "0 (none) with --stop certified: the spectrum "
                             "integrates to t_end; run it with --stop t_end")
    check_spectrum(params, settings, n)
    return n


def carried_of(args: argparse.Namespace, settings: SolverSettings
               ) -> tuple[SolverSettings, CarriedState | None]:
    """The settings naming the carried state of --history run:ID, and that state."""
    _, run_id = parse_history(args.history)
    if run_id is None:
        return settings, None
    end = final_state_of(open_db(args), run_id)
    return replace(settings, history=end.name), end


def json_text(record: dict[str, object], history: str = "constant",
              inputs: tuple[Params, SolverSettings] | None = None) -> str:
    """The record of ``--json``: one JSON object, its keys in JSON_KEYS order, then the
    history the run started from, then what the run was computed at (``params``,
    ``solver``, ``engine``: slopetui.provenance) when its ``inputs`` are given (NaN, ±inf
    as null: slopetui.json_text). ``history`` as given (``run:ID``); a carried state is
    named as export names it, by its state's name (``state:<digest>``, the settings'),
    and ``history_given`` keeps what was typed."""
    facts = {} if inputs is None else computed_at(inputs[0], solver_of(inputs[1], record))
    named = history if inputs is None else inputs[1].history
    given = {} if named == history else {"history_given": history}
    return strict_json({**{k: record[k] for k in JSON_KEYS}, "history": named, **given,
                        **facts})


def solver_of(s: SolverSettings, record: dict[str, object]) -> dict[str, object]:
    """The solver settings the run was asked for, as the store keeps them among a run's
    inputs: the method asked (a stiff fallback is the flag "stiff-fallback"), the step and
    end time as the record resolved them, a carried history by its state's name
    ("state:<digest>")."""
    return {"method": s.method, "dt": record["dt"], "t_end": record["t_end"],
            "window": s.window, "lyap": s.lyap, "history": s.history, "stop": record["stop"]}


def render_text(r: PointResult) -> str:
    s, rec = r.summary, r.as_record()
    p = r.params
    lam = lambda_text(r)
    peaks = ", ".join(f"{v:.6g}" for v in s.peaks) or "none"
    lines = [
        f"point      a={p.a:g} b={p.b:g} c={p.c:g} d={p.d:g} k={p.k:g} v={p.v:g} "
        f"tau={p.tau:g} delta={p.delta:g}",
        f"solver     {r.settings.method}, dt={rec['dt']:g}, t_end={rec['t_end']:g}, "
        f"window={r.settings.window:g}, stop {stop_text(r.settings.stop, rec)}",
        f"regime     {s.regime} ({s.detail})",
        f"lambda_max {lam}",
        f"amplitude  {s.amplitude:.6g}  (peak-to-peak of m_y)",
        f"period     {s.period:.6g}  (return time: {s.period_count} basic period"
        f"{'s' if s.period_count > 1 else ''}, {maxima_words(s.maxima_per_period)})"
        if s.period_count > 0 else f"period     {s.period:.6g}",
        f"attractor  {s.attractor}, {'settled' if s.settled else 'not settled'}"
        + (f"; flags {', '.join(s.flags)}" if s.flags else ""),
        f"peaks      {peaks}",
        f"frequency  {s.frequency:.6g}",
        f"drift      {s.drift:.6g}  (mean dm_x/dt over the window)",
    ]
    if r.spectrum is not None:
        lines.append(f"spectrum   {r.spectrum.format()}  (top {len(r.spectrum.values)}, the m_x "
                     f"shift quotiented out, over the last {r.spectrum.t_measured:g} time units)")
    lines.append(f"certified  {'yes' if r.certificate.certified else 'no'}: {r.certificate.text}")
    real = r.trajectory.realisability  # every step's covariance (core.closure)
    if real is not None:
        lines.append(f"covariance {real.text()}")
    if r.accuracy is not None:  # the scheme's error at its step (core.accuracy)
        lines.append(f"dt error   {r.accuracy.text()}")
    if r.t_blowup is not None:
        lines.append(f"blow-up    at t = {r.t_blowup:.6g}")
    lines.append(f"runtime    {r.runtime_s:.3f} s")
    return "\n".join(lines)


def stop_text(stop: str, rec: dict[str, Any]) -> str:
    """The stop rule and where the run stopped: "t_end", "certified (stopped at t =
    1562.5)", or why a certified run did not stop early."""
    if stop != "certified":
        return stop
    if rec["t_blowup"] is not None:
        return "certified (the run blew up first)"
    if math.isclose(rec["t_stop"], rec["t_end"], rel_tol=1e-9):
        return "certified (not certified before t_end: ran to it)"
    return f"certified (stopped at t = {rec['t_stop']:g})"


def lambda_text(r: PointResult) -> str:
    """lambda_max in the paper's notation, or why there is none or no error bar."""
    if r.lambda_note:  # the certificate's value, not the run's map (core.certified_stop)
        return f"{r.lyap.format() if r.lyap else 'none'}  ({r.lambda_note})"
    if r.lyap is None:
        return "not computed" if not r.settings.lyap else "none (the run blew up)"
    if not math.isfinite(r.lyap.value):
        interval = r.trajectory.grid.renorm_interval
        return (f"not estimated (the run is too short: one log-growth every {interval:g} "
                "time units, and the first half of the run is discarded)")
    note = bias_note(r.params, r.summary.attractor, r.settings.method, r.trajectory.grid.dt,
                     r.lyap.value)
    if not math.isfinite(r.lyap.error):
        return (f"{r.lyap.format()}  (no error: {r.lyap.n_blocks} block of the run's second "
                f"half; {note})")
    return f"{r.lyap.format()}  ({note})"


def handle(args: argparse.Namespace) -> int:
    try:
        params, settings = parse_inputs(args)
        n_exponents = spectrum_count(args, params, settings)
    except ParameterError as exc:
        print(f"slopetui run: error: {exc}", file=sys.stderr)
        return 2
    for w in friction_warnings(params):
        print(f"slopetui run: warning: {w}", file=sys.stderr)

    if not jit_cache.compiled(settings.method):  # a silent pause of seconds looks like a hang
        print(f"slopetui run: compiling the {settings.method} kernel (first use after an "
              "install or a change of the engine; about 4 s, cached after)", file=sys.stderr)
    try:
        settings, carried = carried_of(args, settings)
        result = run_point(params, settings, carried, spectrum=n_exponents)
    except ParameterError as exc:  # a stored run with another tau or step, or none
        print(f"slopetui run: error: {exc}", file=sys.stderr)
        return 2
    if args.json:
        print(json_text(result.as_record(), args.history, (params, settings)))
    else:
        print(render_text(result))
        print(f"history    {args.history}" + (f" ({settings.history})" if carried else ""))
    return 0
