"""A sweep's diagram kept up to date by reading only what changed (the application's
live view; ``slopetui show`` reads a diagram once, ``diagram.load_diagram``).

The first refresh reads the whole sweep; each later one only the runs inserted since
(ids above the highest read) and those that finished since the previous read, less
OVERLAP (``store.diagrams.reads`` says why both keys are safe across hosts). Whatever else
changed (a cancel, a resume, a run given back to the queue) shows in the runs counted per
status, read in the same snapshot: when the copy's counts differ from the store's, the
copy missed something and the whole sweep is read again. A 10,000-run sweep costs one
whole read (~0.3 s) when first shown, then a few ms per refresh.

Queued and running runs count as one kind here, as every drawing shows them (pending):
a run that starts is not read again, so a point's status may say queued while its run is
running; it is read when it finishes.
"""

from __future__ import annotations

import threading
from collections import Counter
from datetime import datetime, timedelta
from typing import Any

from slopetui.store.database import Database
from slopetui.store.diagrams.reads import read_diagram
from slopetui.store.diagrams.result import DiagramRead
from slopetui.sweeps.control import UnknownSweep
from slopetui.sweeps.diagram import RunPoint, SweepDiagram, read_spec, run_points
from slopetui.sweeps.spec import SweepSpec

#: Runs that finished this long before the previous read are read again: a result is
#: stamped (database time) inside its worker's transaction and seen once that commits, a
#: few ms later, more on a loaded server; a result missed even so is caught by the counts.
OVERLAP = timedelta(seconds=10)
#: Statuses that every drawing shows alike (pending), and so are one kind in the counts.
PENDING = frozenset({"queued", "running"})


def kind(status: str) -> str:
    """A run's status as the counts compare it: queued and running are one."""
    return "pending" if status in PENDING else status


class LiveDiagram:
    """One sweep's diagram (``diagram``), brought up to date by ``refresh``. Safe to
    refresh from several threads (one at a time: a lock)."""

    def __init__(self, sweep_id: int) -> None:
        self.sweep_id = sweep_id
        #: The diagram as of the last refresh (None before the first).
        self.diagram: SweepDiagram | None = None
        #: What the last refresh that changed the diagram changed: ``diagram`` is ``base``
        #: with ``changes`` (the points new or changed) put in; base None after a whole
        #: read. A drawing of base can so be brought up to date without redrawing it all.
        self.base: SweepDiagram | None = None
        self.changes: list[RunPoint] = []
        #: Runs read, in all, and whole reads: what the tests and benchmarks look at.
        self.rows_read = 0
        self.whole_reads = 0
        self._lock = threading.Lock()
        self._runs: dict[int, RunPoint] = {}
        #: Per run, what tells a changed row: its status and when it finished.
        self._stamps: dict[int, tuple[str, datetime | None]] = {}
        self._kinds: Counter[str] = Counter()
        self._max_id = 0
        self._since: datetime | None = None

    def refresh(self, db: Database) -> bool:
        """Read what changed since the last refresh; True if the diagram changed.
        Raises UnknownSweep once the sweep is gone (deleted)."""
        with self._lock:
            if self.diagram is None:
                return self._read_whole(db)
            read = read_diagram(db, self.sweep_id, read_spec, after_id=self._max_id,
                                finished_since=self._since)
            if read is None:
                raise UnknownSweep(self.sweep_id)
            changes = self._apply(read)
            store_kinds: Counter[str] = Counter()
            for status, n in read.statuses.items():
                store_kinds[kind(status)] += n
            if +self._kinds != +store_kinds:  # missed a change the keys do not find
                return self._read_whole(db)
            if changes:
                self.base, self.changes = self.diagram, changes
                self._publish(read)
            return bool(changes)

    def state(self) -> tuple[SweepDiagram | None, SweepDiagram | None, list[RunPoint]]:
        """(diagram, base, changes) as one refresh left them: read together, as another
        thread may be refreshing."""
        with self._lock:
            return self.diagram, self.base, self.changes

    def _read_whole(self, db: Database) -> bool:
        read = read_diagram(db, self.sweep_id, read_spec)
        if read is None:
            raise UnknownSweep(self.sweep_id)
        self.whole_reads += 1
        self._runs, self._stamps, self._kinds = {}, {}, Counter()
        self.changes = self._apply(read, whole=True)
        self.base = None
        self._publish(read)
        return True

    def _apply(self, read: DiagramRead[SweepSpec], *, whole: bool = False) -> list[RunPoint]:
        """Take the read's rows into the copy; the points new or changed. The rows of a
        ``whole`` read come in grid order; new runs of another are put in it."""
        self.rows_read += len(read.rows)
        self._max_id = max(self._max_id, read.max_id)
        self._since = read.now - OVERLAP
        has_y = read.spec.y is not None
        status_at, finished_at = read.columns.index("status"), read.columns.index("finished_at")
        changes: list[RunPoint] = []
        inserted = False
        for row, point in zip(read.rows, run_points(read.columns, read.rows, has_y),
                              strict=True):
            stamp = (row[status_at], row[finished_at])
            before = self._stamps.get(point.id)
            if before == stamp:
                continue  # read again within OVERLAP, unchanged
            if before is None:
                inserted = True
            else:
                self._kinds[kind(before[0])] -= 1
            self._kinds[kind(row[status_at])] += 1
            self._stamps[point.id] = stamp
            self._runs[point.id] = point
            changes.append(point)
        if inserted and not whole:
            self._runs = dict(sorted(self._runs.items(), key=_grid_order))
        return changes

    def _publish(self, read: DiagramRead[SweepSpec]) -> None:
        self.diagram = SweepDiagram(read.sweep_id, read.name, read.spec,
                                    list(self._runs.values()))


def _grid_order(item: tuple[int, RunPoint]) -> Any:
    point = item[1]
    return point.ic, point.iy, point.ix
