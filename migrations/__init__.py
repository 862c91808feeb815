"""Alembic migrations of the slopetui store (a package so that wheels carry it).

Applied automatically when a database is opened, or by ``slopetui db upgrade``. A new
revision: change ``slopetui/store/models.py``, then
``.venv/bin/python -m slopetui db revision -m "what changed"`` and review the script.
"""

#: The newest revision. Opening a store compares it with the store's alembic_version in
#: plain SQL, so that a command on an up-to-date store never imports Alembic (~0.3 s).
#: A new revision must update it (tests/unit/test_store.py checks it against Alembic's head).
HEAD = "0017"
