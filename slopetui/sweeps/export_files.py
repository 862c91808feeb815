"""A sweep's runs written as a new file in a folder, in a format of ``slopetui export``:
CSV (``slopetui.sweeps.export.write_csv``, streamed from the store) or JSON (the rows of
``slopetui.sweeps.frames.json_rows``, strict JSON by ``slopetui.json_text``, one run a line).

The application's command palette exports the selected sweep this way into the folder
figures go to. It lives here, not in ``slopetui.cli``, because the faces may not import
each other (the layers of pyproject.toml). Like the figure key, an export never replaces
an earlier file: the name takes -2, -3... when taken, and the file appears whole or not
at all (written beside it under a temporary name, then given the first free name at
once, ``slopetui.whole_files.write_new``: two exports of one sweep at the same time get
two names).
"""

from __future__ import annotations

from collections.abc import Callable
from contextlib import closing
from dataclasses import dataclass
from pathlib import Path
from typing import IO, TYPE_CHECKING

from slopetui.json_text import json_text
from slopetui.store.queries import runs_of, sweep_exists
from slopetui.sweeps.control import UnknownSweep
from slopetui.sweeps.export import write_csv
from slopetui.whole_files import as_text, write_new

if TYPE_CHECKING:
    import pandas as pd

    from slopetui.store.database import Database

#: The formats, as ``slopetui export`` names them (its --parquet needs an optional extra).
FORMATS = ("csv", "json")


@dataclass(frozen=True)
class Exported:
    path: Path
    runs: int


def export_stem(sweep_id: int) -> str:
    """sweep-3-runs: not the figure's sweep-3, whose data file is sweep-3.csv."""
    return f"sweep-{sweep_id}-runs"


def write_json(frame: pd.DataFrame, out: IO[str]) -> int:
    """Strict JSON (no NaN literal: jq and JavaScript refuse it; NaN and ±inf are null,
    slopetui.json_text), one run a line, the text as stored: what ``slopetui export
    --json`` writes."""
    from slopetui.sweeps.frames import json_rows  # pandas: see export_sweep

    rows = json_rows(frame)
    out.write("[\n" if rows else "[")
    out.write(",\n".join(json_text(row, ensure_ascii=False) for row in rows))
    out.write("\n]\n")
    return len(rows)


def export_sweep(db: Database, sweep_id: int, fmt: str, folder: Path) -> Exported:
    """Write the sweep's runs as ``fmt`` (one of FORMATS) into a new file in ``folder``.

    Raises UnknownSweep for a sweep the store does not hold, ValueError for another
    format, OSError if the folder cannot be written to."""
    if fmt not in FORMATS:
        raise ValueError(f"format {fmt!r}: allowed one of {', '.join(FORMATS)}")
    if not sweep_exists(db, sweep_id):
        raise UnknownSweep(sweep_id)
    write: Callable[[IO[str]], int]
    if fmt == "csv":

        def write(out: IO[str]) -> int:
            with closing(runs_of(db, sweep_id)) as runs:  # the session closes if a write fails
                return write_csv(runs, out)
    else:
        # pandas (0.3-0.5 s) loads with the first JSON export, not with the application
        # (which imports this module for its palette) nor with `export --csv`
        from slopetui.sweeps.frames import runs_frame

        frame = runs_frame(db, sweep_id)

        def write(out: IO[str]) -> int:
            return write_json(frame, out)
    # the name is claimed once the file is whole: one picked before writing would be
    # picked by an export started meanwhile too, and the later to finish replaced the other
    return Exported(*write_new(folder, export_stem(sweep_id), fmt, lambda out: as_text(out, write)))
