"""Where the store is when no ``--db`` is given. Light on purpose (no SQLAlchemy), so that
``slopetui --help`` can name the default without loading a database driver."""

from __future__ import annotations

import os
from pathlib import Path
from urllib.parse import quote

from platformdirs import user_data_path

from slopetui.store.failures import StoreError

#: Environment variable that selects the database (any SQLAlchemy URL).
DB_ENV = "SLOPETUI_DB"
#: Environment variable naming a PostgreSQL role's URL that only reads the same database:
#: ``slopetui sql`` and the application's console run their queries under it
#: (slopetui.store.database.Database.read_only_engine; docs/store.md).
READ_DB_ENV = "SLOPETUI_READ_DB"
#: What --db accepts, for its messages.
ALLOWED_URLS = ("allowed a SQLAlchemy URL naming a SQLite file (sqlite:///runs.db) or a "
                "server (postgresql+psycopg://HOST/DB)")


def default_url() -> str:
    """$SLOPETUI_DB, or SQLite in the user data folder (~/.local/share/slopetui on Linux)."""
    env = os.environ.get(DB_ENV)
    if env:
        return env
    return sqlite_url(user_data_path("slopetui") / "slopetui.db")


def sqlite_url(path: Path) -> str:
    """The URL of the SQLite file at ``path`` (absolute): its characters that a URL reads
    as syntax (``?`` a query, ``#`` a fragment, ``%`` an escape, ``@`` and ``:``) escaped, so
    that the URL names that file and no other. (What SQLAlchemy's URL.create renders, here
    without importing SQLAlchemy.)"""
    return f"sqlite:///{quote(str(path), safe='/~')}"


def checked_url(url: str) -> str:
    """``url`` as the user gave it (``--db URL``), or a StoreError naming ``--db`` for a URL
    that would open a store other than the one meant, with nothing created:

    - an empty one, which every ``url or default_url()`` took for "no --db" and answered
      from the default store, creating it;
    - in-memory SQLite (``sqlite://``, ``sqlite:///:memory:``, ``?mode=memory``): a new,
      empty store each time, shown as if it were one and gone when the command ends.

    The rest of the URL's form is SQLAlchemy's to judge (``database.parse_url``).
    """
    if not url.strip():
        raise StoreError(f"--db = {url!r} is empty: {ALLOWED_URLS}; without --db: "
                         f"${DB_ENV}, else the default store")
    scheme, _, rest = url.partition("://")
    path, _, query = rest.partition("?")
    if scheme.split("+")[0].strip().lower() == "sqlite" and (
            path in ("", "/", "/:memory:") or "mode=memory" in query.split("&")):
        raise StoreError(f"--db = {url!r} is an in-memory SQLite database, a new empty store "
                         f"that is gone when the command ends: {ALLOWED_URLS}")
    return url


def url_of(target: str | os.PathLike[str]) -> str:
    """A store named as a notebook names it: a SQLAlchemy URL as it is, or a plain path
    (``"runs/x.db"``, a ``pathlib.Path``) as the URL of that SQLite file, relative to the
    current folder. A URL is told by its ``://``, which no file name a user types holds."""
    if isinstance(target, os.PathLike) or "://" not in target:
        if not os.fspath(target).strip():
            raise StoreError(f"store = {os.fspath(target)!r} is empty: a path to a SQLite "
                             f"file (runs/x.db) or {ALLOWED_URLS.removeprefix('allowed ')}")
        return sqlite_url(Path(os.fspath(target)).expanduser().absolute())
    return target
