"""The final states histories name (core.history.CarriedState, runs.history =
"state:<digest>"): kept once under their name, read back by the worker that computes a
run starting from one and by the run detail that recomputes it."""

from __future__ import annotations

from sqlalchemy import select

from slopetui.store.database import Database
from slopetui.store.models import InitialState


def save_state(db: Database, name: str, blob: bytes, tau: float, dt: float,
               source_run: int | None) -> None:
    """Keep a state under its name (a digest of its content: a state kept already is the
    same state, and stays as it is)."""
    with db.transaction() as s:
        if s.get(InitialState, name) is None:
            s.add(InitialState(name=name, state=blob, tau=tau, dt=dt, source_run=source_run))


def load_state(db: Database, name: str) -> bytes | None:
    """The state kept under ``name``, or None."""
    with db.sessions() as s:
        return s.scalar(select(InitialState.state).where(InitialState.name == name))
