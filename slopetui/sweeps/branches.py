"""Continuations for the faces (the CLI's ``continue --submit`` and ``branch``, the TUI's
branches screen): queue one, list them, read one back with its points and bifurcations
as plain records. No UI here, and no SQL (slopetui.store.jobs.continuations owns it)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from slopetui.queue import branch_jobs
from slopetui.store.database import Database
from slopetui.store.jobs import continuations
from slopetui.store.jobs.continuations import ContinuationRow
from slopetui.sweeps.branch_records import (
    BifurcationRecord,
    PointRecord,
    bifurcation_record,
    point_record,
)
from slopetui.sweeps.stored_jobs import StoredJob

if TYPE_CHECKING:
    from core.branch_start import BranchSpec

@dataclass(frozen=True)
class StoredBranch(StoredJob[ContinuationRow]):
    """A continuation as stored: its row (parameters, status, Hopf point, criticality,
    why it ended), its points so far and, once done, its bifurcations."""

    SUMMARY_KEYS = ("id", "param", "start", "hopf_branch", "status", "from_run", "dt", "end_value",
                    "max_points", "max_step", "hopf_value", "hopf_period", "criticality", "l1",
                    "end_reason", "n_points", "runtime_s", "error", "attempts", "a", "b", "c",
                    "d", "k", "v", "tau", "delta")

    points: list[PointRecord]
    bifurcations: list[BifurcationRecord]


def start_name(row: ContinuationRow) -> str:
    """Where a branch starts, in a word: "hopf2" (the 2nd Hopf point: the second root
    pair's crossing) or "orbit" (a simulated orbit). Stored text: escape it to print."""
    n = row.hopf_branch
    return f"hopf{n}" if row.start == "hopf" and n is not None else str(row.start)


def submit(db: Database, spec: BranchSpec, from_run: int | None = None) -> int:
    """Queue a continuation for the workers; returns its id."""
    return branch_jobs.submit(db, spec, from_run)


def listing(db: Database) -> list[StoredBranch]:
    """Every continuation, newest first, without its points."""
    return [StoredBranch(row, [], []) for row in continuations.continuations(db)]


def branch_of(db: Database, cid: int) -> StoredBranch | None:
    """Continuation ``cid`` with its points and bifurcations; None if there is none."""
    row = continuations.continuation(db, cid)
    if row is None:
        return None
    points = [point_record(p.value, p.period, p.amplitude, p.stable,
                           complex(p.leading_re, p.leading_im))
              for p in continuations.points(db, cid)]
    bifs = [bifurcation_record(b.type, b.value, b.period, complex(b.mu_re, b.mu_im), b.reason)
            for b in continuations.bifurcations(db, cid)]
    return StoredBranch(row, points, bifs)
