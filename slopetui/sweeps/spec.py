"""A sweep spec: one or two axes over model parameters, fixed parameters, solver settings.

The TOML form (``slopetui submit spec.toml``)::

    name = "Fig. 4A: bifurcation in k"
    [x]                      # required: the horizontal axis
    param = "k"              # any of a, b, c, d, k, v, tau, delta
    start = 3
    stop = 24
    num = 43                 # points, both ends included
    spacing = "linear"       # or "log"
    [y]                      # optional: a second axis makes a phase diagram
    param = "tau"
    ...
    [fixed]                  # parameters that are not swept (default: eq. 8)
    delta = 0.1
    [solver]                 # core.SolverSettings (default: Euler, paper settings)
    method = "euler"
    dt = 1e-3
    t_end = 1e5
    window = 1000            # default min(1000, t_end / 2); stored explicitly
    lyap = true
    history = "constant"     # m_x before t = 0: constant (eq. 19) or consistent
    stop = "certified"       # or "t_end": when a run stops (below)
    [adaptive]               # optional, 2-D only: refine the phase diagram adaptively
    levels = 3               # coarse spacing 2**levels lattice steps (1..8)
    [[initial]]              # optional, repeated: compute every point from each of these
    delta = 1e-6             # (default: the sweep's delta)
    [[initial]]
    delta = 0.1
    history = "consistent"   # constant, consistent, or run:ID (a stored run's final
                             # state; default: the solver's history)

With two or more ``[[initial]]`` conditions, each lattice point is computed once per
condition (run column ``ic``), and the diagram shows per cell the common regime or
"depends" (slopetui.sweeps.initial_dependence): the paper's A/B comparison in one map.

``stop`` is when each run stops (core.solve.STOPS): "t_end" integrates to t_end whatever
the run has become (the paper's protocol), "certified" stops it as soon as its attractor
is certified from its own state (a fixed point by its root and decay, an orbit by its
multipliers), else at t_end too. A spec that does not say reads as "t_end": the stored
specs of sweeps before the rule existed ran to t_end, and so do the paper's presets.
New sweeps from ``slopetui submit`` and the application's form default to "certified"
(NEW_SWEEP_STOP: they fill it in before parsing); ``with_stop`` does that.

With ``[adaptive]`` the lattice of x.num x y.num points is the *final* resolution:
only a coarse lattice is computed first, then only where regimes change (see
``slopetui.sweeps.adaptive``); the rest of the lattice is filled by inference.

Every error names the field (``x.num``, ``fixed.tau``...) and what is allowed, and is
raised before anything is written. A new sweep (``parse_spec(..., submitting=True)``) must
also pass the admission checks: the engine's limits on steps and memory per run and on
the window (core.solve.validate_run, at the smallest and the largest tau of the sweep),
and a name without control characters (slopetui.display_text). Specs read back from the
store skip them: they were admitted when they were stored, and a sweep that no longer
loads would stop ``show``, the application and the adaptive refinement.
"""

from __future__ import annotations

import math
import tomllib
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from core.history import check_history
from core.params import PARAM_NAMES, ParameterError, Params
from core.solve import DEFAULT_DT, STOPS, LimitError, SolverSettings, validate_run
from slopetui import examples
from slopetui.display_text import unsafe_characters
from slopetui.sweeps.carried import parse_history

SPACINGS = ("linear", "log")
#: Hard limit: one sweep is one transaction of inserts.
MAX_RUNS = 1_000_000
#: Longest sweep name (characters): it is one line of `status` and of the application.
MAX_NAME = 200

TOP_KEYS = {"name", "x", "y", "fixed", "solver", "adaptive", "initial"}
AXIS_KEYS = {"param", "start", "stop", "num", "spacing"}
SOLVER_KEYS = {"method", "dt", "t_end", "window", "lyap", "history", "stop"}
INITIAL_KEYS = {"delta", "history"}
#: Initial conditions of one sweep at most (each one multiplies its runs).
MAX_INITIAL = 16
ADAPTIVE_KEYS = {"levels"}
#: The stop rule of a new sweep whose spec does not name one (``submit``, the form): a
#: run stops where its attractor is certified, at t_end at the latest. Not the parser's
#: default, which stays the paper's protocol for stored specs and presets (module doc).
NEW_SWEEP_STOP = "certified"
#: Allowed refinement levels: 2**8 = 256 lattice steps between coarse points is already
#: coarser than any useful first look (a 2-D sweep of MAX_RUNS points is 1000 x 1000).
ADAPTIVE_LEVELS = (1, 8)


class SpecError(ValueError):
    """A bad spec: ``field`` is where (e.g. ``x.num``), the message says what is allowed."""

    def __init__(self, field: str, message: str) -> None:
        super().__init__(f"{field}: {message}")
        self.field = field


def _number(field: str, value: object) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise SpecError(field, f"expected a number, got {value!r}")
    try:
        x = float(value)
    except ValueError:
        raise SpecError(field, f"expected a number, got {_short(value)}") from None
    except OverflowError:  # a TOML integer beyond any float
        raise SpecError(field, f"expected a finite number, got {_short(value)}") from None
    if not math.isfinite(x):
        raise SpecError(field, f"expected a finite number, got {value!r}")
    return x


def _short(value: object) -> str:
    """repr of a value for a message, cut to one readable line."""
    shown = repr(value)
    return shown if len(shown) <= 40 else shown[:37] + "..."


def _count(field: str, value: object) -> int:
    x = _number(field, value)
    if x != int(x) or x < 1:
        raise SpecError(field, f"the number of points must be an integer >= 1, got {value!r} "
                               "(an empty range)")
    if x > MAX_RUNS:
        raise SpecError(field, f"at most {MAX_RUNS} points, got {value!r}")
    return int(x)


def _unknown_keys(field: str, given: Mapping[str, Any], allowed: set[str]) -> None:
    extra = sorted(set(given) - allowed)
    if extra:
        where = f"{field}.{extra[0]}" if field else extra[0]
        raise SpecError(where, f"unknown key; allowed: {', '.join(sorted(allowed))}")


@dataclass(frozen=True)
class Axis:
    """``num`` values of ``param`` from ``start`` to ``stop`` (both included)."""

    param: str
    start: float
    stop: float
    num: int
    spacing: str = "linear"

    @classmethod
    def parse(cls, field: str, data: object) -> Axis:
        if not isinstance(data, Mapping):
            raise SpecError(field, "expected a table with param, start, stop, num, spacing")
        _unknown_keys(field, data, AXIS_KEYS)
        for key in ("param", "start", "stop", "num"):
            if key not in data:
                raise SpecError(f"{field}.{key}", "missing")
        param = data["param"]
        if param not in PARAM_NAMES:
            raise SpecError(f"{field}.param", f"unknown parameter {param!r}; one of "
                                              + ", ".join(PARAM_NAMES))
        spacing = data.get("spacing", "linear")
        if spacing not in SPACINGS:
            raise SpecError(f"{field}.spacing", f"{spacing!r}; one of linear, log")
        start = _number(f"{field}.start", data["start"])
        stop = _number(f"{field}.stop", data["stop"])
        num = _count(f"{field}.num", data["num"])
        if num > 1 and start == stop:
            raise SpecError(f"{field}.stop", f"the range is empty: start = stop = {start:g} "
                                             f"with num = {num}")
        if spacing == "log" and (start <= 0 or stop <= 0):
            raise SpecError(f"{field}.start", "log spacing needs start > 0 and stop > 0, "
                                              f"got {start:g} to {stop:g}")
        if not math.isfinite(stop - start):  # linspace would step by infinity: NaN values
            raise SpecError(f"{field}.stop", f"the range {start:g} to {stop:g} is wider than the "
                                             "largest float: allowed |stop - start| <= "
                                             f"{np.finfo(float).max:.4g}")
        return cls(param, start, stop, num, spacing)

    def values(self) -> np.ndarray:
        if self.num == 1:
            return np.array([self.start])
        if self.spacing == "log":
            return np.geomspace(self.start, self.stop, self.num)
        return np.linspace(self.start, self.stop, self.num)


@dataclass(frozen=True)
class InitialCondition:
    """One start of every lattice point: the offset delta of eq. 19 (None: the sweep's)
    and the history before t = 0 (None: the solver's; core.history names it, or run:ID
    names a stored run's final state, which submission replaces by that state's name)."""

    delta: float | None = None
    history: str | None = None


@dataclass(frozen=True)
class SweepSpec:
    """A validated sweep. ``fixed`` holds the parameters that differ from Params()."""

    name: str
    x: Axis
    y: Axis | None = None
    fixed: dict[str, float] = field(default_factory=dict)
    solver: SolverSettings = field(default_factory=SolverSettings)
    #: Refinement levels of an adaptive phase diagram (None: every point is computed).
    adaptive_levels: int | None = None
    #: The initial conditions every point is computed from (empty: the sweep's delta and
    #: the solver's history, one run a point).
    initial: tuple[InitialCondition, ...] = ()

    @property
    def n_lattice(self) -> int:
        """Points of the lattice (for an adaptive sweep: of the final lattice)."""
        return self.x.num * (self.y.num if self.y else 1)

    @property
    def n_runs(self) -> int:
        """Runs of the sweep: one per lattice point and initial condition."""
        return self.n_lattice * max(1, len(self.initial))

    @property
    def conditions(self) -> tuple[tuple[float, str], ...]:
        """(delta, history) of each initial condition, defaults filled in."""
        if not self.initial:
            return ((self.base.delta, self.solver.history),)
        return tuple((self.base.delta if c.delta is None else c.delta,
                      self.solver.history if c.history is None else c.history)
                     for c in self.initial)

    @property
    def first_runs(self) -> int:
        """Runs queued at submission: the whole lattice, or an adaptive sweep's coarse
        lattice (what a ``--yes`` confirmation is about: refinement adds runs only where
        regimes change, and at most the rest of the lattice)."""
        if self.adaptive_levels is None or self.y is None:
            return self.n_runs
        step = 2 ** self.adaptive_levels
        return coarse_count(self.x.num, step) * coarse_count(self.y.num, step)

    @property
    def base(self) -> Params:
        return Params(**self.fixed)

    def points(self, only: Iterable[tuple[int, int]] | None = None
               ) -> Iterator[tuple[int, int, Params]]:
        """(ix, iy, params) for every grid point, x varying fastest; or for the points
        ``only`` (grid indices), in their order."""
        base = self.base
        xs, ys = self.x.values(), (self.y.values() if self.y else [None])
        if only is not None:
            for ix, iy in only:
                p = base.with_(**{self.x.param: float(xs[ix])})
                if self.y is not None:
                    p = p.with_(**{self.y.param: float(self.y.values()[iy])})
                yield ix, iy, p
            return
        for iy, yv in enumerate(ys):
            row = base if self.y is None else base.with_(**{self.y.param: float(yv)})
            for ix, xv in enumerate(xs):
                yield ix, iy, row.with_(**{self.x.param: float(xv)})

    def to_dict(self) -> dict[str, Any]:
        """The JSON-able form stored in sweeps.spec; parse_spec() reads it back."""
        solver = {k: v for k, v in asdict(self.solver).items() if k in SOLVER_KEYS}
        out: dict[str, Any] = {"name": self.name, "x": asdict(self.x),
                               "fixed": dict(self.fixed), "solver": solver}
        if self.y:
            out["y"] = asdict(self.y)
        if self.adaptive_levels is not None:
            out["adaptive"] = {"levels": self.adaptive_levels}
        if self.initial:
            out["initial"] = [{k: v for k, v in asdict(c).items() if v is not None}
                              for c in self.initial]
        return out


def coarse_count(num: int, step: int) -> int:
    """Points of an axis of ``num`` points on a coarse lattice: every ``step``-th index
    and the last one (so that ``num`` need not be 2**levels * m + 1)."""
    return len(range(0, num, step)) + (0 if (num - 1) % step == 0 else 1)


def _parse_fixed(data: object, axes: list[Axis]) -> dict[str, float]:
    if not isinstance(data, Mapping):
        raise SpecError("fixed", "expected a table of parameter = value")
    _unknown_keys("fixed", data, set(PARAM_NAMES))
    swept = {a.param: name for a, name in zip(axes, ("x", "y"), strict=False)}  # one axis or two
    fixed = {}
    for key, value in data.items():
        if key in swept:
            raise SpecError(f"fixed.{key}", f"{key} is swept on {swept[key]}; "
                                            "remove it from [fixed]")
        fixed[key] = _number(f"fixed.{key}", value)
    return fixed


def _parse_solver(data: object) -> SolverSettings:
    if not isinstance(data, Mapping):
        raise SpecError("solver", "expected a table with method, dt, t_end, window, lyap")
    _unknown_keys("solver", data, SOLVER_KEYS)
    kw: dict[str, Any] = {}
    if "method" in data:
        kw["method"] = data["method"]
    for key in ("dt", "t_end", "window"):
        if key in data and data[key] is not None:
            kw[key] = _number(f"solver.{key}", data[key])
    if "lyap" in data:
        if not isinstance(data["lyap"], bool):
            raise SpecError("solver.lyap", f"expected true or false, got {data['lyap']!r}")
        kw["lyap"] = data["lyap"]
    if "history" in data:
        kw["history"] = data["history"]
    if "stop" in data:
        if data["stop"] not in STOPS:  # before SolverSettings, whose message has no quotes
            raise SpecError("solver.stop", f"expected one of {', '.join(map(repr, STOPS))}, "
                                           f"got {_short(data['stop'])}")
        kw["stop"] = data["stop"]
    try:
        settings = SolverSettings(**kw)
    except ParameterError as exc:
        raise SpecError(f"solver.{exc.field}", str(exc)) from None
    if settings.dt is None:  # resolve now: the stored spec and the cache key need it
        settings = SolverSettings(**{**kw, "dt": DEFAULT_DT[settings.method]})
    return settings


def with_stop(data: Mapping[str, Any], stop: str | None = None) -> dict[str, Any]:
    """The spec's tables with the stop rule of a new sweep filled in: ``stop`` if given,
    else the spec's own ``[solver] stop``, else NEW_SWEEP_STOP. A ``solver`` that is not
    a table is left as it is, for parse_spec to name."""
    out = dict(data)
    solver = out.get("solver", {})
    if isinstance(solver, Mapping):
        if stop is not None:
            out["solver"] = {**solver, "stop": stop}
        elif "stop" not in solver:
            out["solver"] = {**solver, "stop": NEW_SWEEP_STOP}
    return out


def _parse_initial(data: object, axes: list[Axis], adaptive: bool
                   ) -> tuple[InitialCondition, ...]:
    """The ``[[initial]]`` conditions: 1 to MAX_INITIAL tables of delta and history."""
    if not isinstance(data, list) or not 1 <= len(data) <= MAX_INITIAL:
        raise SpecError("initial", f"expected 1 to {MAX_INITIAL} tables [[initial]] with delta "
                                   "and/or history")
    if adaptive and len(data) > 1:
        raise SpecError("initial", "an adaptive phase diagram takes one initial condition: "
                                   "remove [adaptive] or keep one [[initial]]")
    out = []
    for i, item in enumerate(data):
        where = f"initial[{i}]"
        if not isinstance(item, Mapping):
            raise SpecError(where, "expected a table with delta and/or history")
        _unknown_keys(where, item, INITIAL_KEYS)
        delta = None
        if "delta" in item:
            if any(a.param == "delta" for a in axes):
                raise SpecError(f"{where}.delta", "delta is swept on an axis; remove it here")
            delta = _number(f"{where}.delta", item["delta"])
            try:
                Params(delta=delta)
            except ParameterError as exc:
                raise SpecError(f"{where}.delta", str(exc)) from None
        history = item.get("history")
        if history is not None:
            try:
                if not (isinstance(history, str) and history.startswith("run:")):
                    check_history(history)
                else:
                    parse_history(history)
            except ParameterError as exc:
                raise SpecError(f"{where}.history", str(exc)) from None
        out.append(InitialCondition(delta, history))
    if len(set(out)) < len(out):
        raise SpecError("initial", "two initial conditions are the same")
    return tuple(out)


def _parse_adaptive(data: object, x: Axis, y: Axis | None) -> int:
    """The refinement levels of an ``[adaptive]`` table (2-D sweeps only)."""
    if not isinstance(data, Mapping):
        raise SpecError("adaptive", "expected a table with levels, e.g. [adaptive] levels = 3")
    _unknown_keys("adaptive", data, ADAPTIVE_KEYS)
    if y is None:
        raise SpecError("adaptive", "adaptive refinement needs a phase diagram: add a [y] "
                                    "axis or remove [adaptive]")
    if "levels" not in data:
        raise SpecError("adaptive.levels", "missing: how many times the coarse lattice is "
                                           f"refined, {ADAPTIVE_LEVELS[0]}..{ADAPTIVE_LEVELS[1]}")
    lo, hi = ADAPTIVE_LEVELS
    value = data["levels"]
    levels = _number("adaptive.levels", value)
    if levels != int(levels) or not lo <= levels <= hi:
        raise SpecError("adaptive.levels", f"expected an integer from {lo} to {hi}, got {value!r}")
    for name, axis in (("x", x), ("y", y)):
        if axis.num < 2:
            raise SpecError(f"{name}.num", "an adaptive phase diagram needs at least 2 points "
                                           f"on each axis, got {axis.num}")
    return int(levels)


def _corners(spec: SweepSpec) -> list[dict[str, float]]:
    """The extreme values of the axes: every grid value lies between an axis' start and
    stop (linear or log spacing alike)."""
    corners: list[dict[str, float]] = [{}]
    for axis in (spec.x, spec.y):
        if axis is not None:
            corners = [{**c, axis.param: v} for c in corners for v in (axis.start, axis.stop)]
    return corners


def _check_points(spec: SweepSpec, submitting: bool) -> None:
    """Every grid point must be a valid Params, and dt must fit every tau; when
    submitting, every run must also be within the engine's limits (validate_run).

    Checking the corners of the grid is enough, and costs O(1) instead of O(points) (a
    100 x 100 sweep took 76 ms point by point, too slow for a form that re-validates on
    every keystroke): Params's constraints are bounds on single parameters (tau, d,
    k >= 0, finite), and dt only has to fit the smallest tau. The grid of a run depends on
    tau alone: its delay ring grows with tau, its steps and lambda_max logs are largest at
    the smallest tau, so both ends are checked. (A tau between them may round to a
    slightly finer effective step, dt' = tau / ceil(tau / dt) >= dt / 2: a run that then
    crosses a limit fails at its worker with the same message, before it allocates.)
    """
    try:
        base = spec.base
    except ParameterError as exc:
        raise SpecError(f"fixed.{exc.field}", str(exc)) from None
    corners = []
    try:
        corners = [base.with_(**c) for c in _corners(spec)]
    except ParameterError as exc:
        axis = next((name for name, a in (("x", spec.x), ("y", spec.y))
                     if a is not None and a.param == exc.field), "fixed")
        raise SpecError(f"{axis}.{exc.field}", str(exc)) from None
    by_tau = sorted(corners, key=lambda p: p.tau)
    for point in dict.fromkeys((by_tau[0], by_tau[-1])):
        try:
            validate_run(point, spec.solver)
        except LimitError as exc:
            if submitting:
                raise SpecError(_grid_field(spec, exc.field, point.tau), str(exc)) from None
        except ParameterError as exc:
            raise SpecError(_grid_field(spec, exc.field, point.tau), str(exc)) from None


def _grid_field(spec: SweepSpec, field: str, tau: float) -> str:
    """Where in the spec a grid error's field is: tau on its axis end or in [fixed], the
    rest in [solver]."""
    if field != "tau":
        return f"solver.{field}"
    for name, axis in (("x", spec.x), ("y", spec.y)):
        if axis is not None and axis.param == "tau":
            return f"{name}.start" if axis.start == tau else f"{name}.stop"
    return "fixed.tau"


def parse_spec(data: Mapping[str, Any], *, submitting: bool = False) -> SweepSpec:
    """Validate a spec given as a mapping (a parsed TOML file, or sweeps.spec).

    ``submitting``: a new sweep, which must also pass the admission checks (module doc);
    False reads back a stored spec, or checks a draft.
    """
    if not isinstance(data, Mapping):
        raise SpecError("spec", f"expected a table of keys, got {_short(data)}")
    _unknown_keys("", data, TOP_KEYS)
    if "x" not in data:
        raise SpecError("x", "missing: a sweep needs at least the [x] axis")
    x = Axis.parse("x", data["x"])
    y = Axis.parse("y", data["y"]) if data.get("y") is not None else None
    if y is not None and y.param == x.param:
        raise SpecError("y.param", f"{y.param} is already swept on x")
    axes = [x] + ([y] if y else [])
    name = _parse_name(data.get("name"), submitting) or _default_name(x, y)
    adaptive = data.get("adaptive")
    initial = data.get("initial")
    spec = SweepSpec(name=name, x=x, y=y, fixed=_parse_fixed(data.get("fixed", {}), axes),
                     solver=_parse_solver(data.get("solver", {})),
                     adaptive_levels=None if adaptive is None else _parse_adaptive(adaptive, x, y),
                     initial=() if initial is None else _parse_initial(initial, axes,
                                                                       adaptive is not None))
    if spec.n_runs > MAX_RUNS:
        raise SpecError("x.num", f"{spec.n_runs} runs; at most {MAX_RUNS} per sweep")
    _check_points(spec, submitting)
    return spec


def _parse_name(name: object, submitting: bool) -> str:
    """The name given, or "" for none (blank: the default name is made from the axes)."""
    if name is None:
        return ""
    if not isinstance(name, str) or len(name) > MAX_NAME:
        got = f"{len(name)} characters" if isinstance(name, str) else _short(name)
        raise SpecError("name", f"expected a string of at most {MAX_NAME} characters, got {got}")
    bad = unsafe_characters(name)
    if submitting and bad:  # shown on other users' terminals: see slopetui.display_text
        raise SpecError("name", f"control characters are not allowed ({', '.join(bad)}): "
                                "allowed printable text, as it is shown on terminals")
    return name if name.strip() else ""


def _default_name(x: Axis, y: Axis | None) -> str:
    if y is None:
        return f"{x.param} {x.start:g}..{x.stop:g}"
    return f"{x.param} {x.start:g}..{x.stop:g} x {y.param} {y.start:g}..{y.stop:g}"


def read_spec(source: str | Path) -> dict[str, Any]:
    """The tables of a TOML spec: the file at ``source``, else the shipped example of that
    name (a file always wins, so a local fig4a.toml is never shadowed). SpecError (field:
    the source) if there is neither, or the file cannot be read, or it is not UTF-8 TOML
    (a binary file, a directory). The one loader of spec files: parse_spec validates."""
    path = Path(source)
    if not path.exists():
        try:
            text = examples.text(str(source))
        except KeyError:
            raise SpecError(str(source), "no such file, and no shipped example of that name "
                                         f"(examples: {', '.join(examples.names())})") from None
        return _toml_tables(text, f"example {source}")
    try:
        text = path.read_text(encoding="utf-8")
    except IsADirectoryError:
        raise SpecError(str(path), "is a directory: expected a TOML spec file") from None
    except OSError as exc:
        raise SpecError(str(path), f"cannot read the spec file: {exc.strerror}") from None
    except UnicodeDecodeError as exc:
        raise SpecError(str(path), f"not a text file: byte {exc.start} is not UTF-8 (expected "
                                   "a TOML spec file)") from None
    return _toml_tables(text, str(path))


def _toml_tables(text: str, where: str) -> dict[str, Any]:
    """Parse a spec's TOML text; ``where`` names it in the error."""
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SpecError(where, f"not valid TOML: {exc}") from None


def parse_axis_flag(field: str, text: str) -> dict[str, Any]:
    """``PARAM=START:STOP:NUM[:log]`` (the --x/--y flags) as an axis table."""
    param, sep, rest = text.partition("=")
    parts = rest.split(":")
    if not sep or len(parts) not in (3, 4):
        raise SpecError(field, f"expected PARAM=START:STOP:NUM[:log|linear], got {text!r}")
    axis: dict[str, Any] = {"param": param.strip(), "start": parts[0], "stop": parts[1],
                            "num": parts[2]}
    if len(parts) == 4:
        axis["spacing"] = parts[3]
    return axis
