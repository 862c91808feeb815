"""Pause, resume and cancel sweeps; ``apply`` dispatches an action by name for the faces
(``slopetui pause|resume|cancel`` and the application's keys) and says what happened."""

from __future__ import annotations

from slopetui.store.database import Database
from slopetui.store.sweep_rows import cancel_sweep, set_sweep_status


class UnknownSweep(LookupError):
    def __init__(self, sweep_id: int) -> None:
        super().__init__(f"SWEEP: no sweep with id {sweep_id}")


def _set_status(db: Database, sweep_id: int, status: str, allowed_from: tuple[str, ...]) -> str:
    current = set_sweep_status(db, sweep_id, status, allowed_from)
    if current is None:
        raise UnknownSweep(sweep_id)
    return current


def pause(db: Database, sweep_id: int) -> str:
    """Its queued runs stay queued but are not handed out; running runs finish."""
    return _set_status(db, sweep_id, "paused", ("active",))


def resume(db: Database, sweep_id: int) -> str:
    return _set_status(db, sweep_id, "active", ("paused",))


def cancel(db: Database, sweep_id: int) -> int:
    """Cancel the sweep's queued runs (running ones finish); returns how many."""
    n = cancel_sweep(db, sweep_id)
    if n is None:
        raise UnknownSweep(sweep_id)
    return n


#: The actions by name, as the faces offer them.
ACTIONS = ("pause", "resume", "cancel")


def apply(db: Database, action: str, sweep_id: int) -> str:
    """Pause, resume or cancel a sweep; the outcome on one line, e.g. "sweep 3 is paused"
    or "sweep 3 cancelled: 12 queued runs cancelled". Raises UnknownSweep, and ValueError
    for an action that is not in ACTIONS."""
    if action == "cancel":
        return f"sweep {sweep_id} cancelled: {cancel(db, sweep_id)} queued runs cancelled"
    if action == "pause":
        return f"sweep {sweep_id} is {pause(db, sweep_id)}"
    if action == "resume":
        return f"sweep {sweep_id} is {resume(db, sweep_id)}"
    raise ValueError(f"unknown sweep action {action!r}; one of {', '.join(ACTIONS)}")
