"""Hysteresis sweeps for the faces (the CLI's ``hysteresis --submit`` and ``--show``, the
TUI's branches screen): queue one, list them, read one back with its points as plain
records. No UI here, and no SQL (slopetui.store.jobs.hysteresis_sweeps owns it)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from slopetui.queue import hysteresis_jobs
from slopetui.queue.hysteresis_jobs import HysteresisSpec
from slopetui.store.database import Database
from slopetui.store.jobs import hysteresis_sweeps
from slopetui.store.jobs.hysteresis_sweeps import HysteresisPointRow, HysteresisRow
from slopetui.sweeps.stored_jobs import StoredJob

#: value, regime, amplitude (peak to peak of m_y), detail, growth (1 / time unit), jumped,
#: direction ("up" or "down"); NaN where core.hysteresis.WarmPoint has NaN.
WarmRecord = dict[str, Any]


@dataclass(frozen=True)
class StoredHysteresis(StoredJob[HysteresisRow]):
    """A hysteresis sweep as stored: its row (parameters, status, where each branch
    changes regime) and its points so far, in sweep order (up, then down)."""

    SUMMARY_KEYS = ("id", "param", "status", "start", "stop", "n_points", "n_done", "dt",
                    "t_settle", "window", "tol", "onset_up", "onset_up_before",
                    "onset_up_after", "offset_down", "offset_down_before",
                    "offset_down_after", "runtime_s", "error",
                    "attempts", "a", "b", "c", "d", "k", "v", "tau", "delta")

    points: list[WarmRecord]

    @property
    def up(self) -> list[WarmRecord]:
        return [p for p in self.points if p["direction"] == "up"]

    @property
    def down(self) -> list[WarmRecord]:
        return [p for p in self.points if p["direction"] == "down"]


def warm_record(row: HysteresisPointRow) -> WarmRecord:
    return {"value": row.value, "regime": row.regime, "amplitude": row.amplitude,
            "detail": row.detail, "growth": row.growth, "jumped": bool(row.jumped),
            "direction": row.direction}


def submit(db: Database, spec: HysteresisSpec) -> int:
    """Queue a hysteresis sweep for the workers; returns its id."""
    return hysteresis_jobs.submit(db, spec)


def listing(db: Database) -> list[StoredHysteresis]:
    """Every hysteresis sweep, newest first, without its points."""
    return [StoredHysteresis(row, []) for row in hysteresis_sweeps.hysteresis_sweeps(db)]


def hysteresis_of(db: Database, sid: int) -> StoredHysteresis | None:
    """Hysteresis sweep ``sid`` with its points; None if there is none."""
    row = hysteresis_sweeps.hysteresis_sweep(db, sid)
    if row is None:
        return None
    return StoredHysteresis(row, [warm_record(p) for p in hysteresis_sweeps.points(db, sid)])


__all__ = ["HysteresisRow", "HysteresisSpec", "StoredHysteresis", "WarmRecord", "hysteresis_of",
           "listing", "submit"]
