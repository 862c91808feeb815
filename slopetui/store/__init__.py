"""The experiment store: SQLAlchemy models of sweeps, runs and workers, the one module
that owns engines, sessions and transactions, the Alembic migrations ``open_store``
applies, and every SQL statement behind a name, in a module named for what it holds:
the faces' reads (``queries``); runs (``runs``: their claims, the result cache, speeds,
initial states, the notebooks' frames); sweeps (``sweeps``: writes, progress, an adaptive
sweep's refinement); a sweep's diagram (``diagrams``); jobs under a lease (``jobs``: the
one lease, point-by-point jobs, continuations, hysteresis sweeps, the backlog); and the
workers (``workers``).

The package exports nothing: a name is imported from the module that defines it
(``from slopetui.store.open import open_store``, ``from slopetui.store.database import
Database``), so that a light module (``slopetui.store.location``) is imported without
SQLAlchemy.
"""
