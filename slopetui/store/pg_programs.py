"""Where PostgreSQL's programs live when they are not on PATH: the store's downgrade
backup looks there for pg_dump (slopetui.store.server_dump), ``db serve`` for initdb,
pg_ctl and postgres (slopetui.ops.local_server)."""

from __future__ import annotations

import re
from pathlib import Path

#: Where distributions put the server programs when they are not on PATH (newest wins).
PG_BIN_GLOBS = ("/usr/lib/postgresql/*/bin", "/usr/pgsql-*/bin",
                "/opt/homebrew/opt/postgresql@*/bin", "/usr/local/opt/postgresql@*/bin")


def distribution_folders() -> list[Path]:
    """The folders of PG_BIN_GLOBS that exist, in its order, the newest version first
    within each pattern (a newer pg_dump dumps an older server, not the reverse)."""
    found: list[Path] = []
    for pattern in PG_BIN_GLOBS:
        found.extend(sorted(Path("/").glob(pattern.lstrip("/")),
                            key=lambda p: [int(n) for n in re.findall(r"\d+", str(p))],
                            reverse=True))
    return found
