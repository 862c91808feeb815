"""Pause, resume, cancel and delete sweeps; ``apply`` dispatches an action by name for the
faces (``slopetui pause|resume|cancel|delete`` and the application's keys) and says what
happened, so that the command line and the application print the same line.

Cancel is undone by resume: a cancelled sweep's cancelled runs (it cancels only queued
runs) go back to the queue as they were, and the sweep is active again. An adaptive
sweep then goes on refining: the runs of its current level are queued again, and once
they finish a worker's idle poll queues the next level (``sweeps.adaptive``: cancelled
sweeps do not advance, active ones do). Delete is not undone by anything: the faces ask
first (``slopetui delete`` on a terminal or with --yes, the application's modal), and it
refuses while runs of the sweep are running (``store.sweeps.writes.delete_sweep`` says why;
``SweepBusy`` says what to do: cancel an active sweep, wait for a cancelled one).
"""

from __future__ import annotations

from dataclasses import dataclass

from slopetui.store.database import Database
from slopetui.store.queries import sweep_status
from slopetui.store.sweeps.writes import (
    Deletion,
    cancel_sweep,
    delete_sweep,
    resume_sweep,
    set_sweep_status,
)

__all__ = ["ACTIONS", "Deletion", "Resumed", "SweepBusy", "UnknownSweep", "apply", "cancel",
           "delete", "pause", "resume"]


class UnknownSweep(LookupError):
    def __init__(self, sweep_id: int, field: str = "SWEEP") -> None:
        super().__init__(f"{field}: no sweep with id {sweep_id}")


class SweepBusy(RuntimeError):
    """The sweep has running runs: it cannot be deleted now (nothing was written).

    What to do depends on its ``status``: an active sweep keeps handing runs out, so it is
    cancelled first; a cancelled (or paused) one hands out nothing more, and its running
    runs, in a worker's kernel or claimed in its batch, finish or give up on their own:
    cancelling it again would change nothing, so the message says to wait, and where to
    see them."""

    def __init__(self, sweep_id: int, running: int, status: str = "active") -> None:
        runs = "run is" if running == 1 else "runs are"
        busy = f"sweep {sweep_id} cannot be deleted while {running} of its {runs} running"
        if status == "active":
            super().__init__(f"{busy}: cancel it (slopetui cancel {sweep_id}, or c), wait "
                             "for them to finish, then delete it")
        else:
            them = "it" if running == 1 else "them"
            super().__init__(
                f"{busy}: the sweep is {status}, so nothing more is handed out; wait for "
                f"{them} to finish or give up in the workers (slopetui runs --sweep "
                f"{sweep_id} --status running, or the queue screen, 2), then delete it")
        self.sweep_id, self.running, self.status = sweep_id, running, status


@dataclass(frozen=True)
class Resumed:
    """The sweep's status after a resume, and how many cancelled runs went back to the
    queue (0 unless it was cancelled)."""

    status: str
    requeued: int


def _set_status(db: Database, sweep_id: int, status: str, allowed_from: tuple[str, ...]) -> str:
    current = set_sweep_status(db, sweep_id, status, allowed_from)
    if current is None:
        raise UnknownSweep(sweep_id)
    return current


def pause(db: Database, sweep_id: int) -> str:
    """Its queued runs stay queued but are not handed out; running runs finish."""
    return _set_status(db, sweep_id, "paused", ("active",))


def resume(db: Database, sweep_id: int) -> Resumed:
    """A paused sweep's runs are handed out again; a cancelled sweep's cancelled runs are
    queued again (with the attempts they had: see store.sweeps.writes.resume_sweep) and it
    is active."""
    out = resume_sweep(db, sweep_id, ("paused", "cancelled"))
    if out is None:
        raise UnknownSweep(sweep_id)
    return Resumed(*out)


def cancel(db: Database, sweep_id: int) -> int:
    """Cancel the sweep's queued runs (running ones finish); returns how many."""
    n = cancel_sweep(db, sweep_id)
    if n is None:
        raise UnknownSweep(sweep_id)
    return n


def delete(db: Database, sweep_id: int) -> Deletion:
    """Delete the sweep and its runs, in one transaction; other sweeps' runs that copied
    a result from them keep it. Raises UnknownSweep, and SweepBusy (nothing deleted)
    while runs of it are running."""
    out = delete_sweep(db, sweep_id)
    if out is None:
        raise UnknownSweep(sweep_id)
    if out.running:
        raise SweepBusy(sweep_id, out.running, sweep_status(db, sweep_id) or "active")
    return out


#: What each action does, in a sentence: the faces' help (the application's help screen,
#: from the keys' tooltips) says it the same way wherever the key is.
EXPLAINED = {
    "pause": "Stop handing out the sweep's runs (they stay queued)",
    "resume": "Hand out a paused sweep's runs again; a cancelled sweep's cancelled runs "
              "are queued again",
    "cancel": "Cancel the sweep's queued runs (asks first; running ones finish; r resumes)",
    "delete": "Delete the sweep and its runs (asks first; not while runs of it are running)",
}

#: The actions by name, as the faces offer them.
ACTIONS = ("pause", "resume", "cancel", "delete")


def _runs(n: int, what: str = "") -> str:
    """"1 run", "1072 cancelled runs" (no thousands separator: as the cancel line)."""
    return f"{n} {what}{'run' if n == 1 else 'runs'}"


def apply(db: Database, action: str, sweep_id: int) -> str:
    """Pause, resume, cancel or delete a sweep; the outcome on one line, e.g. "sweep 3 is
    paused", "sweep 3 cancelled: 12 queued runs cancelled", "sweep 3 resumed: 12
    cancelled runs queued again" or "sweep 3 deleted with its 40 runs". Raises
    UnknownSweep, SweepBusy (delete), and ValueError for an action not in ACTIONS."""
    if action == "cancel":
        return f"sweep {sweep_id} cancelled: {cancel(db, sweep_id)} queued runs cancelled"
    if action == "pause":
        return f"sweep {sweep_id} is {pause(db, sweep_id)}"
    if action == "resume":
        # the status before is not read apart (one transaction decides): a resume that
        # requeued nothing reads as the status, as for a paused sweep
        out = resume(db, sweep_id)
        if out.requeued:
            return (f"sweep {sweep_id} resumed: {_runs(out.requeued, 'cancelled ')} "
                    "queued again")
        return f"sweep {sweep_id} is {out.status}"
    if action == "delete":
        gone = delete(db, sweep_id)
        kept = (f"; {_runs(gone.copies_kept)} of other sweeps keep the results they "
                "copied from it" if gone.copies_kept else "")
        return f"sweep {sweep_id} deleted with its {_runs(gone.runs)}{kept}"
    raise ValueError(f"unknown sweep action {action!r}; one of {', '.join(ACTIONS)}")
