"""What the faces read of any stored point-by-point job (a continuation:
slopetui.sweeps.branches, a hysteresis sweep: slopetui.sweeps.hysteresis_runs): its row,
its id and parameter, and the row's fields a reader wants."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar, Generic, Protocol, TypeVar


class JobRow(Protocol):
    """A point-by-point job's row as the store reads it (slopetui.store.jobs.continuations
    .ContinuationRow, hysteresis_sweeps.HysteresisRow): its fields are its columns."""

    @property
    def id(self) -> int: ...

    @property
    def param(self) -> str: ...


R = TypeVar("R", bound=JobRow)


@dataclass(frozen=True)
class StoredJob(Generic[R]):
    """A job's row as stored (parameters, status, results); each kind adds what it read
    beside it (its points, ...) and names in ``SUMMARY_KEYS`` the row's fields a reader
    wants (no worker bookkeeping)."""

    SUMMARY_KEYS: ClassVar[tuple[str, ...]] = ()

    row: R

    @property
    def id(self) -> int:
        return int(self.row.id)

    @property
    def param(self) -> str:
        return str(self.row.param)

    def summary(self) -> dict[str, Any]:
        """The row's fields a reader wants (``SUMMARY_KEYS``), in that order."""
        return {key: getattr(self.row, key) for key in self.SUMMARY_KEYS}
