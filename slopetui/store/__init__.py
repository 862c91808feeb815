"""The experiment store: SQLAlchemy models of sweeps, runs and workers, the one module
that owns engines, sessions and transactions, and the Alembic migrations applied on open."""

from slopetui.store.database import Database, default_url
from slopetui.store.models import RUN_STATUSES, SWEEP_STATUSES, Base, Run, Sweep, Worker

__all__ = ["RUN_STATUSES", "SWEEP_STATUSES", "Base", "Database", "Run", "Sweep", "Worker",
           "default_url"]
