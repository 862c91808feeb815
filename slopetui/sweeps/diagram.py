"""A sweep's runs as diagram data: grid positions, axis values, regimes and peaks.

An adaptive sweep's inferred runs come back like done ones (status done, their regime)
with ``inferred`` true; lattice points without a run yet (levels not queued yet) are
listed by ``SweepDiagram.unqueued`` so that drawings show them as pending.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from slopetui.store.diagrams.sqlite_reads import NeedsDatabase, read_sqlite_diagram
from slopetui.sweeps.hopf_plane import Curve, hopf_boundary
from slopetui.sweeps.spec import SweepSpec, parse_spec

if TYPE_CHECKING:  # SQLAlchemy's: imported where a Database is read (``load_drawing``)
    from slopetui.store.database import Database


@dataclass(frozen=True)
class RunPoint:
    id: int
    ix: int
    iy: int
    x: float
    y: float | None
    status: str
    regime: str | None      # None unless done
    peaks: list[float]      # peak clusters of m_y; a sliding run gives its mean m_y
    error: str | None
    detail: str | None = None
    period_count: int | None = None
    lambda_max: float = float("nan")
    lambda_err: float = float("nan")
    drift: float = float("nan")  # window mean of m_y
    inferred: bool = False  # an adaptive sweep's regime taken from its cell's corners
    attractor: str | None = None  # fixed-point, fast-branch, periodic, torus, ... (done runs)
    flags: tuple[str, ...] = ()   # stiff-fallback, linear-transient, ... (core.classify)
    maxima_per_period: int | None = None
    settled: bool | None = None
    ic: int = 0  # which of the sweep's initial conditions (spec [[initial]])
    delta: float = float("nan")
    history: str = "constant"
    #: The attractor was certified (core.point: None before migration 0012 or not done),
    #: and how, or why not.
    certified: bool | None = None
    certificate: str | None = None


@dataclass(frozen=True)
class SweepDiagram:
    id: int
    name: str
    spec: SweepSpec
    runs: list[RunPoint]

    @property
    def n_done(self) -> int:
        return sum(r.status == "done" for r in self.runs)

    @property
    def n_inferred(self) -> int:
        return sum(r.inferred for r in self.runs)

    @property
    def n_computed(self) -> int:
        """Done runs that were computed (or copied from a computed run), not inferred."""
        return sum(r.status == "done" and not r.inferred for r in self.runs)

    @property
    def n_points(self) -> int:
        """Runs the sweep will have: one per point of its lattice and initial condition
        (an adaptive sweep has runs for some so far)."""
        return self.spec.n_runs

    def unqueued(self) -> list[tuple[int, int, float, float | None]]:
        """(ix, iy, x, y) of the lattice points that have no run yet: an adaptive sweep's
        points of levels not queued yet, and those it will infer."""
        if len(self.runs) >= self.n_points:
            return []
        have = {(r.ix, r.iy) for r in self.runs}
        xs = self.spec.x.values()
        ys = self.spec.y.values() if self.spec.y else [None]
        return [(ix, iy, float(x), None if y is None else float(y))
                for iy, y in enumerate(ys) for ix, x in enumerate(xs) if (ix, iy) not in have]


def plane_hopf(spec: SweepSpec) -> Curve | None:
    """The exact Hopf curve over a 2-D sweep's plane, or None where the plane has none."""
    assert spec.y is not None
    x, y = spec.x, spec.y
    return hopf_boundary(spec.base, x.param, y.param,
                         (min(x.start, x.stop), max(x.start, x.stop)),
                         (min(y.start, y.stop), max(y.start, y.stop)))


def read_spec(stored: dict[str, Any]) -> tuple[SweepSpec, str, str | None]:
    """A stored spec as the store's diagram read wants it: the spec, its x and y params."""
    spec = parse_spec(stored)
    return spec, spec.x.param, spec.y.param if spec.y else None


#: A run's measurements where a row read ``drawn_only`` has none: RunPoint's defaults.
UNMEASURED: dict[str, Any] = {"peaks": None, "drift": math.nan, "error": None, "detail": None,
                              "period_count": None, "lambda_max": math.nan,
                              "lambda_err": math.nan, "attractor": None, "flags": None,
                              "maxima_per_period": None, "settled": None, "certified": None,
                              "certificate": None}


def run_points(columns: Sequence[str], rows: Iterable[Sequence[Any]],
               has_y: bool) -> list[RunPoint]:
    """Runs of a diagram read (``store.diagrams.result.DiagramRead``: values in ``columns``
    order) as a diagram's points (their measurements NaN or None where the read had
    none)."""
    absent = {k: v for k, v in UNMEASURED.items() if k not in columns}
    measured = not absent
    points = []
    for row in rows:
        m = dict(absent)
        m.update(zip(columns, row, strict=True))
        points.append(run_point(m, has_y, measured=measured))
    return points


def run_point(m: dict[str, Any], has_y: bool, *, measured: bool = True) -> RunPoint:
    """A run of a diagram read (its columns by name) as a diagram's point; ``measured``
    False for a row read without its measurements (no peaks then)."""
    done = m["status"] == "done"
    regime, flags = m["regime"], m["flags"]
    # A sliding run has no peaks: it rests near the fixed point m_y = 0 (eqs. 14-17;
    # with noise d > 0 it drifts at a small constant m_y). It is drawn at its window
    # mean of m_y (the drift), the flat lower branch of Fig. 4A. So is a run whose window
    # still sits at an unstable rest state (core.classify: not departed), whatever regime
    # it is headed for: the diagram shows what the window shows.
    at_rest = regime == "sliding" or m["attractor"] == "unstable-fixed-point"
    shown = (([m["drift"]] if at_rest else list(m["peaks"] or []))
             if done and measured else [])
    return RunPoint(m["id"], m["ix"], m["iy"], m["x"], m["y"] if has_y else None, m["status"],
                    regime if done else None, shown, m["error"],
                    m["detail"] if done else None, m["period_count"] if done else None,
                    m["lambda_max"], m["lambda_err"], m["drift"], bool(m["inferred"]),
                    m["attractor"] if done else None,
                    tuple(flags.split(",")) if done and flags else (),
                    m["maxima_per_period"] if done else None,
                    m["settled"] if done else None, m["ic"], m["delta"], m["history"],
                    m["certified"] if done else None, m["certificate"] if done else None)


def load_diagram(db: Database, sweep_id: int, *, drawn_only: bool = False) -> SweepDiagram:
    """Everything a phase or bifurcation diagram of the sweep needs, in one read. With
    ``drawn_only``, a phase diagram's runs come without their measurements (peaks,
    lambda_max...): what a drawing in the terminal shows, read in about half the time (a
    1-D sweep is read whole: its drawing shows the peaks)."""
    # here, as the store's other imports below: `show` reads a SQLite file without
    # SQLAlchemy (load_drawing), and SQLAlchemy costs it 0.3-0.4 s
    from slopetui.store.diagrams.reads import read_diagram

    read = read_diagram(db, sweep_id, read_spec, drawn_only=drawn_only)
    if read is None:
        from slopetui.sweeps.control import UnknownSweep
        raise UnknownSweep(sweep_id)
    return SweepDiagram(read.sweep_id, read.name, read.spec,
                        run_points(read.columns, read.rows, read.spec.y is not None))


def load_drawing(url: str | None, sweep_id: int | None,
                 say: Callable[[str], None] | None = None) -> SweepDiagram | None:
    """What a drawing of a sweep needs (``load_diagram(..., drawn_only=True)``), from the
    store at ``url`` (default: ``$SLOPETUI_DB``, else the default file), which it opens
    and closes: the sweep ``sweep_id``, or the newest one if None; None if the store has
    no sweep. Raises UnknownSweep if there is no sweep ``sweep_id``.

    A SQLite file at the current schema is read without SQLAlchemy
    (``store.diagrams.sqlite_reads``, 0.35-0.45 s less for `slopetui show`); any other
    store is opened with ``open_store`` (created, migrated) and read by ``load_diagram``;
    a SQLite file this user cannot write is opened read-only, and ``say`` is told so.
    """
    try:
        read = read_sqlite_diagram(url, sweep_id, read_spec, drawn_only=True)
    except NeedsDatabase:
        return _load_drawing_through_database(url, sweep_id, say)
    if read is None:
        if sweep_id is None:
            return None
        from slopetui.sweeps.control import UnknownSweep
        raise UnknownSweep(sweep_id)
    return SweepDiagram(read.sweep_id, read.name, read.spec,
                        run_points(read.columns, read.rows, read.spec.y is not None))


def _load_drawing_through_database(url: str | None, sweep_id: int | None,
                                   say: Callable[[str], None] | None) -> SweepDiagram | None:
    from slopetui.store.open import open_store
    from slopetui.store.queries import newest_sweep_id

    db = open_store(url, read_only_ok=say is not None)
    if db.read_only is not None and say is not None:
        say(db.read_only)
    try:
        if sweep_id is None:
            sweep_id = newest_sweep_id(db)
            if sweep_id is None:
                return None
        return load_diagram(db, sweep_id, drawn_only=True)
    finally:
        db.dispose()
