"""The experiment store: SQLAlchemy models of sweeps, runs and workers, the one module
that owns engines, sessions and transactions, the Alembic migrations ``open_store``
applies, and every SQL statement behind a name, in a module named for what it holds:
the faces' reads (``queries``); runs (``runs``: their claims, the result cache, speeds,
initial states, the notebooks' frames); sweeps (``sweeps``: writes, progress, an adaptive
sweep's refinement); a sweep's diagram (``diagrams``); jobs under a lease (``jobs``: the
one lease, point-by-point jobs, continuations, hysteresis sweeps, the backlog); and the
workers (``workers``).

Inside the project a name is imported from the module that defines it (``from
slopetui.store.open import open_store``), so that a light module
(``slopetui.store.location``) is imported without SQLAlchemy. For scripts and notebooks
the names below are also the package's, imported on first use (PEP 562).
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

_EXPORTS = {
    "Database": "slopetui.store.database", "open_store": "slopetui.store.open",
    "default_url": "slopetui.store.location",
    "RUN_STATUSES": "slopetui.store.statuses", "SWEEP_STATUSES": "slopetui.store.statuses",
    "Base": "slopetui.store.models", "Run": "slopetui.store.models",
    "Sweep": "slopetui.store.models", "Worker": "slopetui.store.models",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str) -> Any:
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'slopetui.store' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


if TYPE_CHECKING:
    from slopetui.store.database import Database
    from slopetui.store.location import default_url
    from slopetui.store.models import Base, Run, Sweep, Worker
    from slopetui.store.open import open_store
    from slopetui.store.statuses import RUN_STATUSES, SWEEP_STATUSES
