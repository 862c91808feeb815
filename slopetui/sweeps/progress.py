"""Progress of sweeps and the live workers, as plain data (for `status` and the TUI), and
the pool's progress line (``PoolProgress``, handed to the pool by the faces that start one).
The live workers are the queue's (``slopetui.queue.workers_table``), re-exported here.

An adaptive sweep's total is its final lattice; its runs exist only for the levels
queued so far, so done/total grows in steps and reaches the total when the inferred
runs are written. It is ``done`` only then: between two levels nothing is queued, but
the next level is still to come. ``stage`` says where it is ("level 2/3", "refined").

A sweep with nothing left to compute whose runs all failed is ``failed``, not ``done``:
the word would say it is complete when not one run gave a result. ``done`` counts the
runs with a result only; ``failed`` and ``cancelled`` count the others apart, and the
faces show each for what it is (``slopetui status``'s columns, the application's bar:
done green, failed red, cancelled dim), never one share that reaches 100% when every run
failed. The pool's progress line counts failed runs as finished (nothing is left to
wait for) and says how many failed.

Runs per minute. While a sweep has runs to compute, its rate is the recent one: its
computed runs finished in the last RATE_WINDOW_MIN minutes, over the time since the
earliest start among them. A sweep with nothing left (done, failed, or cancelled with
nothing running) would see that rate decay to 0 as its last runs leave the window: its
rate is then its final one, over its whole life, its computed runs over the time from
the first start to the last finish among them (pauses included: the time it took).
``rate_final`` says which.

Running runs. A worker claims runs in batches (``store.claims``): a run claimed is
'running' at once, but computed only when its turn in the batch comes (started_at is
set then). ``claimed_text`` says so, "39 runs claimed in batches on 2 workers (8
computing, 31 waiting their turn)", for the application's queue screen and ``slopetui
status``.
"""

from __future__ import annotations

from dataclasses import dataclass
from datetime import datetime, timedelta

from slopetui.duration_text import duration_text
from slopetui.queue.workers_table import WorkerInfo, live_workers
from slopetui.store.database import Database
from slopetui.store.sweeps.progress import active_sweep_ids, running_runs, sweep_tallies

__all__ = ["RATE_WINDOW_MIN", "PoolProgress", "SweepProgress", "WorkerInfo", "claimed_line",
           "claimed_text", "live_workers", "sweep_progress"]

#: Runs per minute are measured over the runs finished in this trailing window (minutes).
RATE_WINDOW_MIN = 10.0


@dataclass(frozen=True)
class SweepProgress:
    id: int
    name: str
    axes: str              # "k" or "k x tau"
    status: str            # active, paused, cancelled; done when nothing is left (failed
                           # when nothing is left and no run is done)
    created_at: datetime
    total: int
    counts: dict[str, int]  # runs per status
    cached: int             # done runs that took an earlier result
    runs_per_min: float     # computed runs finished per minute: recent window, or the
                            # whole life once nothing is left (rate_final); 0 if none
    eta_s: float | None     # None when idle or nothing left (adaptive: this level's runs)
    adaptive_levels: int | None = None  # None: every point is computed
    level: int | None = None            # the level queued last (adaptive)
    refined: bool = False               # adaptive: refinement over, inferred runs written
    inferred: int = 0                   # runs inferred, not computed (among done/failed)
    rate_final: bool = False            # runs_per_min is over the sweep's whole life
    recent_per_min: float = 0.0         # the recent window's rate, finished or not

    @property
    def done(self) -> int:
        return self.counts.get("done", 0)

    @property
    def failed(self) -> int:
        return self.counts.get("failed", 0)

    @property
    def cancelled(self) -> int:
        """Runs cancelled before they ran (resume queues them again)."""
        return self.counts.get("cancelled", 0)

    @property
    def running(self) -> int:
        return self.counts.get("running", 0)

    @property
    def left(self) -> int:
        return self.counts.get("queued", 0) + self.counts.get("running", 0)

    @property
    def computed(self) -> int:
        """Done runs that were computed (or copied from a computed run)."""
        return self.done + self.failed - self.inferred

    @property
    def stage(self) -> str:
        """"level 2/3" or "refined" for an adaptive sweep, "" for others."""
        if self.adaptive_levels is None:
            return ""
        return "refined" if self.refined else f"level {self.level}/{self.adaptive_levels}"


def sweep_progress(db: Database, sweep_ids: list[int] | None = None) -> list[SweepProgress]:
    """Progress of the given sweeps (default: all), newest first."""
    t = sweep_tallies(db, sweep_ids, timedelta(minutes=RATE_WINDOW_MIN))
    now, since, cached, inferred, recent = t.now, t.since, t.cached, t.inferred, t.recent
    out = []
    for sw in t.sweeps:
        c = t.counts.get(sw.id, {})
        left = c.get("queued", 0) + c.get("running", 0)
        finished = left == 0 and (sw.adaptive_levels is None or sw.refined)
        status = sw.status
        if finished and status != "cancelled":
            status = "failed" if c.get("failed", 0) and not c.get("done", 0) else "done"
        n, first = recent.get(sw.id, (0, None))
        recent_rate = _per_min(n, (now - max(first, since)) if first else None)
        final = left == 0 and status in ("done", "failed", "cancelled")
        rate = recent_rate
        if final:  # its whole life (module docstring)
            n, first, last = t.lifetime.get(sw.id, (0, None, None))
            rate = _per_min(n, (last - first) if first and last else None)
        eta = left / rate * 60.0 if rate > 0 and left and status == "active" else None
        axes = sw.x_param + (f" x {sw.y_param}" if sw.y_param else "")
        out.append(SweepProgress(sw.id, sw.name, axes, status, sw.created_at, sw.n_runs,
                                 dict(c), cached.get(sw.id, 0), rate, eta, sw.adaptive_levels,
                                 sw.level, sw.refined, inferred.get(sw.id, 0), final,
                                 recent_rate))
    return out


def _per_min(n: int, span: timedelta | None) -> float:
    """``n`` runs over ``span``, per minute; 0 without a span. A floor of one second on
    the span: a lone run that took no time is no infinite rate."""
    if not n or span is None:
        return 0.0
    return n / max(span.total_seconds() / 60.0, 1 / 60)


def claimed_text(held: int, begun: int, workers: int) -> str:
    """The runs workers hold, said for what they are: "39 runs claimed in batches on 2
    workers (8 computing, 31 waiting their turn)" (a batch's runs are claimed together and
    computed in turn: "39 running" read as 39 computations on 2 workers); "2 runs
    computing on 2 workers" when every held run has begun; "" when none is held.
    ``held``: running runs; ``begun``: those of them with started_at set
    (``store.sweeps.progress.running_runs``); ``workers``: the live workers."""
    if not held:
        return ""
    runs = "run" if held == 1 else "runs"
    if not workers:  # a dead pool's: requeued by the next worker's look at the leases
        return f"{held} {runs} held by no live worker: queued again when their lease runs out"
    on = f"on {workers} {'worker' if workers == 1 else 'workers'}"
    waiting = held - begun
    if not waiting:
        return f"{held} {runs} computing {on}"
    return (f"{held} {runs} claimed in batches {on} ({begun} computing, {waiting} waiting "
            "their turn)")


def claimed_line(db: Database, workers: int) -> str:
    """claimed_text of the runs the store holds as running now, all sweeps."""
    return claimed_text(*running_runs(db), workers)


class PoolProgress:
    """The pool's progress line, "12/240 runs done, 30.1 runs/min, ETA 7m48s", over the
    sweeps that were active while the pool ran; None when the count has not changed.
    The pool (slopetui.queue.pool) calls ``PoolProgress(db)`` once, then the instance at
    most every PROGRESS_S seconds."""

    def __init__(self, db: Database) -> None:
        self.db = db
        self.sweeps: set[int] = set()
        self.last: tuple[int, int] | None = None

    def __call__(self) -> str | None:
        self.sweeps |= active_sweep_ids(self.db)
        if not self.sweeps:
            return None
        mine = sweep_progress(self.db, sorted(self.sweeps))
        total = sum(p.total for p in mine)
        finished = sum(p.done + p.failed for p in mine)
        if (finished, total) == self.last:
            return None
        self.last = (finished, total)
        # the workers' recent throughput, finished sweeps included
        rate = sum(p.recent_per_min for p in mine)
        left = sum(p.left for p in mine if p.status == "active")
        failed = sum(p.failed for p in mine)
        text = f"{finished}/{total} runs done" + (f" ({failed} failed)" if failed else "")
        if not left:
            return text + "; nothing queued"
        eta = left / rate * 60.0 if rate > 0 else None
        return f"{text}, {rate:.1f} runs/min, ETA {duration_text(eta)}"
