"""The experiment store: SQLAlchemy models of sweeps, runs and workers, the one module
that owns engines, sessions and transactions, the Alembic migrations ``open_store``
applies, and every SQL statement behind a name: the faces' reads
(``slopetui.store.queries``), the queue's (``claims``, ``cached_results``,
``worker_rows``) and the sweeps' (``sweep_rows``, ``sweep_reads``, ``diagram_reads``,
``adaptive_rows``).

The package exports nothing: a name is imported from the module that defines it
(``from slopetui.store.open import open_store``, ``from slopetui.store.database import
Database``), so that a light module (``slopetui.store.location``) is imported without
SQLAlchemy.
"""
