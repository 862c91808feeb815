"""What a result was computed at: its parameters, its solver and its engine. Every output
that holds a result names them (docs/outputs.md), in one of two shapes built here:

* **nested**, in the JSON of one computation (``run``, ``continue``, ``hysteresis``,
  ``orbit --json``): ``"params": {a, b, c, d, k, v, tau, delta}``, ``"solver": {method,
  dt, ...}`` and ``"engine": {"version", "digest"}``, beside the result's own keys;
* **flat**, in a table of runs (``export --csv / --json / --parquet``): the parameters and
  the solver settings are columns already, the engine is two more, ``engine_version`` and
  ``engine_digest`` (a nested key ``engine.version`` is the column ``engine_version``).

**The engine.** Its digest is ``core.jit_cache.source_digest()``, the hash of core/*.py
that keys the kernel cache, the result cache and the run detail's comparison: one owner,
read here, never computed again. A run computed now carries this installation's digest and
version. A stored result carries the digest stored with it (the ``engine`` column of
``runs``, ``continuations``, ``hysteresis_sweeps``: written at queue time, then by the
worker that computes it, with its own digest; "mixed" for a continuation or hysteresis
sweep whose points workers of different engines saved); the store keeps no version, so
its version is this installation's only when the digests agree, and null (an empty cell)
otherwise: a version that was not recorded is not guessed.

**A figure** names the same facts (``figure_facts``): in its PDF or SVG metadata, in a
comment line at the top of the CSV beside it, and in its optional one-line caption.

This module is light (no numpy, no numba): ``export --csv`` imports it
(tests/integration/test_startup.py).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from functools import lru_cache
from typing import Any

from core.jit_cache import source_digest
from core.params import PARAM_NAMES
from slopetui import __version__

__all__ = ["ENGINE_COLUMNS", "caption", "computed_at", "engine", "engine_version_of",
           "params_of", "this_engine"]

#: The engine's columns of a flat table (export --csv, --json, --parquet), in order.
ENGINE_COLUMNS: tuple[str, ...] = ("engine_version", "engine_digest")


@lru_cache(maxsize=1)  # the sources do not change under a running process that uses them
def _digest() -> str:
    return source_digest()


def this_engine() -> dict[str, str]:
    """The engine of a computation made now: this installation's version and digest."""
    return {"version": __version__, "digest": _digest()}


def engine_version_of(digest: str | None) -> str | None:
    """The package version a stored run's engine digest was computed with, where it is
    known: this installation's version if the digest is this installation's, else None
    (the store keeps the digest only)."""
    return __version__ if digest is not None and digest == _digest() else None


def engine(digest: str | None) -> dict[str, str | None]:
    """The engine of a stored result, from the digest stored with it (module docstring)."""
    return {"version": engine_version_of(digest), "digest": digest}


def params_of(params: Any) -> dict[str, float]:
    """The eight parameters (a, b, c, d, k, v, tau, delta) of a Params, a stored row or a
    mapping of them."""
    if isinstance(params, Mapping):
        return {n: float(params[n]) for n in PARAM_NAMES}
    return {n: float(getattr(params, n)) for n in PARAM_NAMES}


def computed_at(params: Any, solver: Mapping[str, Any], digest: str | None = None, *,
                start: tuple[str, float | None] | None = None) -> dict[str, Any]:
    """The three keys every JSON of one computation adds: params, solver, engine
    (``digest`` None: computed now, by this installation). ``start``: (the parameter a
    continuation follows, the value its branch starts at), which replaces the value in
    ``params`` (a Hopf point is not where the user's value was); None there: the start is
    not known yet (no point saved), and the parameter is null, not a value the branch
    never had."""
    named: dict[str, float | None] = {**params_of(params)}
    if start is not None:
        named[start[0]] = None if start[1] is None else float(start[1])
    return {"params": named, "solver": dict(solver),
            "engine": this_engine() if digest is None else engine(digest)}


def _number(value: Any) -> str:
    return f"{value:g}" if isinstance(value, float) else str(value)


def caption(facts: Mapping[str, Any], varied: Sequence[str] = ()) -> str:
    """One line of the facts for a figure's caption: "a=0.5 ... delta=1e-05; rk4, dt=0.01,
    t_end=1000, ...; slopetui 0.1.0, engine 1f2e...". ``varied`` names parameters that
    the figure varies (an axis), and solver settings that differ between the runs it
    compares: they are written as "k varied", not as one value; a setting that is None
    (a history that differs between initial conditions, listed apart) is left out."""
    params = facts.get("params", {})
    words = [f"{n} varied" if n in varied else f"{n}={_number(params[n])}"
             for n in PARAM_NAMES if n in params or n in varied]
    solver = facts.get("solver", {})
    settings = [f"{k} varied" if k in varied else
                str(v) if k == "method" else f"{k}={_number(v)}"
                for k, v in solver.items() if v is not None or k in varied]
    eng = facts.get("engine", {})
    version, digest = eng.get("version"), eng.get("digest")
    if digest is None:  # a sweep's figure before any of its runs is done
        return f"{' '.join(words)}; {', '.join(settings)}; no runs done"
    made = f"slopetui {version}" if version else "slopetui version not recorded"
    return f"{' '.join(words)}; {', '.join(settings)}; {made}, engine {digest}"
