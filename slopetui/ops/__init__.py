"""Operations around the store, not persistence: a PostgreSQL server of one's own
(``slopetui db serve``: local_server), the connection budget a worker pool shares
(connection_slots) and the Slurm script of a cluster's workers (slurm).

ops may use the store; the store never imports ops (an import-linter contract): a
Database takes its connection budget as anything with ``acquire``, ``release`` and
``held`` (slopetui.store.connection_budget.ConnectionBudget).
"""
