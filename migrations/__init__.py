"""Alembic migrations of the slopetui store (a package so that wheels carry it).

Applied automatically when a database is opened, or by ``slopetui db upgrade``. A new
revision: change ``slopetui/store/models.py``, then
``.venv/bin/python -m slopetui db revision -m "what changed"`` and review the script.
"""
