"""What a figure was computed at, in the shape every output uses (slopetui.provenance):
``params``, ``solver``, ``engine``, and what the figure shows (``sweep`` or ``runs``).

* **A sweep's figure** (its phase or bifurcation diagram) draws the stored results: its
  params are the sweep's fixed parameters, ``varied`` naming its axes (their params null:
  no one value), its solver the
  spec's, its engine the digests its done runs were computed with (``sweep_engines``: one,
  unless the engine changed while the sweep was computed; then their digests joined by
  ", " and no version). A sweep from several initial conditions (``[[initial]]``) lists
  them under ``initial`` (delta and history of each); a delta that differs between them is
  ``varied`` (null among the params), and a history that differs is null in the solver.
* **A run's figure** redraws the run from its stored inputs with this installation's
  engine (slopetui.sweeps.recompute): its ``engine`` is this one, and ``stored_engine``
  the digest of the stored result its title quotes. Several runs: one entry each under
  ``runs``, and the common facts (a parameter or a solver setting that differs between
  them is ``varied``, and null among the common params or solver).

The facts go into the figure's metadata, a comment line at the top of each CSV beside it
and, on request, its one-line caption (slopetui.figures.output.write).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from core.params import PARAM_NAMES
from slopetui.provenance import caption, computed_at, engine, params_of, this_engine

if TYPE_CHECKING:
    from slopetui.sweeps.diagram import SweepDiagram
    from slopetui.sweeps.recompute import StoredRun

#: The solver settings a run keeps among its inputs, in the order outputs name them.
SOLVER_KEYS = ("method", "dt", "t_end", "window", "lyap", "history", "stop")


def sweep_facts(diagram: SweepDiagram, engines: Sequence[str]) -> dict[str, Any]:
    """The facts of a sweep's figure; ``engines``: the digests of its done runs."""
    spec = diagram.spec
    varied = [spec.x.param] + ([spec.y.param] if spec.y is not None else [])
    solver = {key: getattr(spec.solver, key) for key in SOLVER_KEYS}
    conditions = spec.conditions
    initial: dict[str, Any] = {}
    if len(conditions) > 1:  # several [[initial]]: no one delta or history (module docstring)
        initial = {"initial": [{"delta": d, "history": h} for d, h in conditions]}
        if len({d for d, _ in conditions}) > 1 and "delta" not in varied:
            varied.append("delta")
        if len({h for _, h in conditions}) > 1:
            solver["history"] = None
        else:
            solver["history"] = conditions[0][1]
    if len(engines) == 1:
        eng: dict[str, Any] = engine(engines[0])
    else:  # none done yet, or several engines: no one version
        eng = {"version": None, "digest": ", ".join(engines) or None}
    base = spec.base.with_(delta=conditions[0][0])  # the one delta, if the conditions share it
    facts = {"sweep": diagram.id, "varied": varied, **computed_at(base, solver), **initial,
             "engine": eng}
    return _without_varied(facts)


def _without_varied(facts: dict[str, Any]) -> dict[str, Any]:
    """The facts with each varied parameter as None (null): it has no one value."""
    return {**facts, "params": {n: None if n in facts["varied"] else v
                                for n, v in facts["params"].items()}}


def _run_facts(run: StoredRun) -> dict[str, Any]:
    return {"run": run.id, **computed_at(run, {key: getattr(run, key) for key in SOLVER_KEYS}),
            "engine": this_engine(), "stored_engine": run.engine}


def runs_facts(runs: Sequence[StoredRun]) -> dict[str, Any]:
    """The facts of a figure of one run, or of several compared (module docstring)."""
    each = [_run_facts(run) for run in runs]
    if len(each) == 1:
        return each[0]
    first = each[0]
    varied = [n for n in PARAM_NAMES if any(f["params"][n] != first["params"][n] for f in each)]
    differ = [key for key, value in first["solver"].items()
              if any(f["solver"][key] != value for f in each)]
    varied += differ  # a setting that differs has no one value either: null, as a parameter
    solver = {key: None if key in differ else value for key, value in first["solver"].items()}
    return _without_varied({"runs": each, "varied": varied, "params": params_of(first["params"]),
                            "solver": solver, "engine": this_engine()})


def figure_caption(facts: dict[str, Any]) -> str:
    """The facts as one line: what the figure shows, then slopetui.provenance.caption."""
    if "sweep" in facts:
        shows = f"sweep {facts['sweep']}"
    elif "runs" in facts:
        shows = "runs " + ", ".join(str(f["run"]) for f in facts["runs"])
    else:
        shows = f"run {facts['run']}"
    return f"{shows}: {caption(facts, facts.get('varied', ()))}"
