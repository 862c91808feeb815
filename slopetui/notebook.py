"""The store for notebooks: ``slopetui.open_store(url)`` and its runs and sweeps as pandas
DataFrames. A face, beside the application and the report: it runs no SQL of its own
(the store's named reads do, through ``slopetui.sweeps.frames``).

Usage::

    import slopetui

    with slopetui.open_store("sqlite:////data/slopetui.db") as store:
        sweeps = store.sweeps()              # one row per sweep, runs counted per status
        runs = store.runs(sweep=3)           # every column of `slopetui export 3 --csv`
        chaotic = store.runs(sweep=3, regime="complex")
        paper = store.runs(tag="paper")      # the runs of the sweeps tagged paper

    runs.plot.scatter("k", "lambda_max")

Without a URL the store is the default one, as for every command: ``$SLOPETUI_DB``, else
the SQLite file in the user data folder. What the columns hold, their dtypes, and how a
run that was never measured differs from a NaN measurement: ``slopetui.sweeps.frames``.
"""

from __future__ import annotations

import os
from types import TracebackType
from typing import TYPE_CHECKING

from slopetui.store.location import url_of
from slopetui.store.open import open_store as open_database
from slopetui.sweeps.annotations import check_tag
from slopetui.sweeps.control import UnknownSweep
from slopetui.sweeps.frames import runs_frame, sweeps_frame

if TYPE_CHECKING:
    import pandas as pd

    from slopetui.store.database import Database

__all__ = ["Store", "open_store"]


class Store:
    """An open store, read as DataFrames. ``close()`` it when done, or use it in a ``with``
    block::

        with slopetui.open_store() as store:
            df = store.runs(sweep=3)
            df[df.status == "done"].groupby("regime").size()

    ``database`` is the underlying ``slopetui.store.database.Database`` (for the library's
    other functions, which take one).
    """

    def __init__(self, database: Database) -> None:
        self.database = database
        self._closed = False

    @property
    def url(self) -> str:
        """The store's URL, any password hidden."""
        return self.database.display_url

    def _db(self) -> Database:
        if self._closed:
            raise ValueError(f"the store {self.url} is closed: slopetui.open_store() again")
        return self.database

    def runs(self, sweep: int | None = None, *, regime: str | None = None,
             status: str | None = None, tag: str | None = None) -> pd.DataFrame:
        """The runs of ``sweep`` (None: of every sweep), of this regime (done runs with it)
        and this status (queued, running, done, failed, cancelled), of the sweeps tagged
        ``tag`` (``slopetui tag``), None meaning any:
        one row per run in grid order, with the columns of ``slopetui export SWEEP
        --csv``. Raises UnknownSweep for a sweep the store does not hold.

        A run's results are missing unless it is done; an inferred run (adaptive sweeps)
        has its regime only. Filter on ``status`` and ``inferred`` to tell "not measured"
        from a measured NaN::

            measured = runs[(runs.status == "done") & ~runs.inferred]
        """
        if tag is not None:
            tag = check_tag(tag)  # "Paper" finds what `slopetui tag 3 Paper` stored as paper
        return runs_frame(self._db(), sweep, regime=regime, status=status, tag=tag)

    def sweeps(self) -> pd.DataFrame:
        """Every sweep, one row each by id: name, status, creation time, the x and y axes
        (parameter, start, stop, num, spacing), adaptive levels, and its runs counted per
        status (queued, running, done, failed, cancelled), inferred and cached; the
        columns are described in ``slopetui.sweeps.frames.SWEEP_COLUMNS``."""
        return sweeps_frame(self._db())

    def sweep(self, sweep_id: int) -> pd.Series:
        """One sweep's row of ``sweeps()``. Raises UnknownSweep if there is none."""
        frame = sweeps_frame(self._db(), [sweep_id])
        if frame.empty:
            raise UnknownSweep(sweep_id)
        return frame.iloc[0]

    def close(self) -> None:
        """Close the store's connections; a closed store reads nothing more."""
        if not self._closed:
            self._closed = True
            self.database.dispose()

    def __enter__(self) -> Store:
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        self.close()

    def __repr__(self) -> str:
        # no query here: a repr must not fail or wait on an unreachable server
        state = "closed" if self._closed else ".sweeps(), .runs(sweep=ID)"
        return f"<slopetui.Store {self.url} ({state})>"


def open_store(url: str | os.PathLike[str] | None = None) -> Store:
    """The store at ``url``: a SQLAlchemy URL (``sqlite:////path/to/file.db``,
    ``postgresql+psycopg://host/db``) or a plain path to a SQLite file (``"runs/x.db"``, a
    ``pathlib.Path``; relative to the current folder), default ``$SLOPETUI_DB``, else the
    SQLite file in the user data folder; migrated to the current schema first, as every
    command does.

        >>> store = slopetui.open_store("data/slopetui.db")
        >>> store.sweeps()[["id", "name", "status", "done", "n_runs"]]
        >>> store.runs(sweep=3).plot.scatter("k", "tau", c="lambda_max")
        >>> store.close()
    """
    import sys

    db = open_database(None if url is None else url_of(url), read_only_ok=True)  # a Store only reads
    if db.read_only is not None:
        print(f"slopetui.open_store: {db.read_only}", file=sys.stderr)
    return Store(db)
