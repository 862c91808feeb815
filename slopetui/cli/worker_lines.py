"""The line that shows one live worker, as ``slopetui status`` and ``slopetui workers``
both print it: its id, what it computes (a run, a continuation, a hysteresis sweep, or
nothing), the jobs it has done and the age of its heartbeat."""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

from slopetui.display_text import terminal_safe
from slopetui.duration_text import duration_text

if TYPE_CHECKING:
    from slopetui.queue.workers_table import WorkerInfo


def worker_line(w: WorkerInfo, held: Mapping[str, Mapping[str, int]]) -> str:
    """``held``: by a kind of job's label (slopetui.queue.registry.activity: "branch",
    "hysteresis"), the job of that kind each worker computes, by worker id. Stored text
    (the id) goes through terminal_safe."""
    doing = f"run {w.run_id}" if w.run_id else next(
        (f"{label} {jobs[w.id]}" for label, jobs in held.items() if w.id in jobs), "idle")
    return (f"worker {terminal_safe(w.id):28} {doing:12} {w.jobs_done:>6} done  "
            f"heartbeat {duration_text(w.heartbeat_age_s)} ago")
