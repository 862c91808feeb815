"""Curves in two parameters for the faces (the CLI's ``continue --param2 --submit`` and
``curve``, the TUI's branches screen): queue one, list them, read one back with its points
and codimension-two points as plain records. No UI here, and no SQL
(slopetui.store.jobs.curves owns it)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from slopetui.queue import curve_jobs
from slopetui.store.database import Database
from slopetui.store.jobs import curves
from slopetui.store.jobs.curves import CurvePointRow, CurveRow
from slopetui.sweeps.curve_records import multiplier_fields
from slopetui.sweeps.stored_jobs import StoredJob

if TYPE_CHECKING:
    from core.curve_start import CurveSpec


#: What each kind of curve is a curve of, in words.
CURVE_NAMES = {"fold": "fold of cycles", "hopf": "Hopf curve", "pd": "period doubling",
               "ns": "torus (Neimark-Sacker)"}


@dataclass(frozen=True)
class StoredCurve(StoredJob[CurveRow]):
    """A curve as stored: its row (parameters, status, why it ended), its points so far
    and, once done, its codimension-two points; records keyed by the parameters' names, as
    ``continue --param2 --json`` prints them."""

    SUMMARY_KEYS = ("id", "kind", "param", "param2", "hopf_branch", "branch_end", "status", "dt",
                    "end_value",
                    "max_points", "max_step", "end_reason", "n_points", "runtime_s", "error", "attempts",
                    "a", "b", "c", "d", "k", "v", "tau", "delta")

    points: list[dict[str, Any]]
    bifurcations: list[dict[str, Any]]

    @property
    def second(self) -> str:
        return str(self.row.param2)


def submit(db: Database, spec: CurveSpec) -> int:
    """Queue a curve for the workers; returns its id."""
    return curve_jobs.submit(db, spec)


def listing(db: Database) -> list[StoredCurve]:
    """Every curve, newest first, without its points."""
    return [StoredCurve(row, [], []) for row in curves.curves(db)]


def point_record(name: str, second: str, p: CurvePointRow, kind: str = "fold"
                 ) -> dict[str, Any]:
    """A stored point as ``continue --param2 --json`` prints a computed one (the largest
    multiplier but the bifurcation's own, read from the stored ones)."""
    out: dict[str, Any] = {name: p.first, second: p.second, "period": p.period}
    if p.l1 is not None:
        return {**out, "l1": p.l1, "criticality": "supercritical" if p.l1 < 0 else "subcritical"}
    return {**out, **multiplier_fields(p.amplitude, _multipliers(p) if p.multipliers else None,
                                       kind)}


def _multipliers(p: CurvePointRow) -> Any:
    """The stored multipliers as core.floquet.Multipliers (by modulus, as saved)."""
    import numpy as np  # light at start: only a stored point with multipliers

    from core.floquet import Multipliers
    values = np.array([complex(re, im) for re, im in (p.multipliers or [])])
    return Multipliers(values, int(p.flow_index or 0), float(p.translation or 1.0))


def curve_of(db: Database, cid: int) -> StoredCurve | None:
    """Curve ``cid`` with its points and codimension-two points; None if there is none."""
    row = curves.curve(db, cid)
    if row is None:
        return None
    name, second = row.param, row.param2
    points = [point_record(name, second, p, row.kind) for p in curves.points(db, cid)]
    found = [{"type": b.type, name: b.first, second: b.second, "period": b.period,
              "note": b.note} for b in curves.bifurcations(db, cid)]
    return StoredCurve(row, points, found)
