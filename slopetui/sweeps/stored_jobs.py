"""What the faces read of any stored point-by-point job (a continuation:
slopetui.sweeps.branches, a hysteresis sweep: slopetui.sweeps.hysteresis_runs): its row,
its id and parameter, and the row's fields a reader wants."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar


@dataclass(frozen=True)
class StoredJob:
    """A job's row as stored (parameters, status, results); each kind adds what it read
    beside it (its points, ...) and names in ``SUMMARY_KEYS`` the row's fields a reader
    wants (no worker bookkeeping)."""

    SUMMARY_KEYS: ClassVar[tuple[str, ...]] = ()

    row: Any

    @property
    def id(self) -> int:
        return int(self.row["id"])

    @property
    def param(self) -> str:
        return str(self.row["param"])

    def summary(self) -> dict[str, Any]:
        """The row's fields a reader wants (``SUMMARY_KEYS``), in that order."""
        return {key: self.row[key] for key in self.SUMMARY_KEYS}
