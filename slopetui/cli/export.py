"""``slopetui export SWEEP --csv | --parquet | --json``: a sweep's runs as a file (the
formats: ``slopetui.sweeps.export`` for CSV, ``slopetui.sweeps.frames`` for the DataFrame
that Parquet and JSON are written from)."""

from __future__ import annotations

import argparse
import errno
import os
import sys
from collections.abc import Callable
from contextlib import closing
from pathlib import Path
from typing import IO, TYPE_CHECKING

from slopetui.cli.options import UsageError, open_db, sweep_arg
from slopetui.cli.runs import csv_to_stdout, text_to_stdout
from slopetui.display_text import terminal_safe
from slopetui.store.queries import runs_of, sweep_exists
from slopetui.sweeps.control import UnknownSweep
from slopetui.sweeps.export import write_csv
from slopetui.sweeps.export_files import write_json
from slopetui.whole_files import as_text, write_whole

if TYPE_CHECKING:
    import pandas as pd

    from slopetui.store.database import Database


#: The one line of an export --parquet without pyarrow (an optional extra).
NO_PYARROW = "export --parquet needs pyarrow: pip install 'slopetui[parquet]'"


def handle(args: argparse.Namespace) -> int:
    sweep = sweep_arg(args.sweep)
    if args.output is not None and not args.output.strip():  # before: stdout, as without -o
        raise UsageError(f"--output = {args.output!r} is empty: allowed a file name")
    if args.format == "parquet":  # refused before the store is opened: nothing written
        _need_pyarrow()
        if not args.output and sys.stdout.isatty():
            raise UsageError("export --parquet writes binary data: give -o FILE, or send "
                             "stdout to a file or a pipe (not a terminal)")
    db = open_db(args)
    if not sweep_exists(db, sweep):
        raise UnknownSweep(sweep)
    if args.format == "csv":
        n = _export_csv(db, sweep, args.output)
    else:
        n = _export_frame(db, sweep, args.format, args.output)
    if args.output:
        print(f"{n} runs of sweep {sweep} written to {terminal_safe(args.output)}",
              file=sys.stderr)
    return 0


def _export_csv(db: Database, sweep: int, output: str | None) -> int:
    """The sweep's runs as CSV, streamed from the store, to ``output`` or stdout."""

    with closing(runs_of(db, sweep)) as runs:
        if not output:
            return csv_to_stdout(runs)
        return _write_file(output, lambda out: as_text(out, lambda text: write_csv(runs, text)))


def _export_frame(db: Database, sweep: int, form: str, output: str | None) -> int:
    """The sweep's runs as Parquet or JSON, from their DataFrame, to ``output`` or stdout."""
    from slopetui.sweeps.frames import runs_frame  # pandas: not for `export --csv`

    frame = runs_frame(db, sweep)
    if output:
        if form == "parquet":
            return _write_file(output, lambda out: _parquet(frame, out))
        return _write_file(output, lambda out: as_text(out, lambda text: _json(frame, text)))
    if form == "parquet":  # not a terminal: handle refused that
        sys.stdout.flush()
        _parquet(frame, sys.stdout.buffer)
        sys.stdout.buffer.flush()
        return len(frame)
    return text_to_stdout(lambda text: _json(frame, text))


def _need_pyarrow() -> None:
    try:
        import pyarrow  # noqa: F401
    except ImportError:
        raise UsageError(NO_PYARROW) from None


def _json(frame: pd.DataFrame, out: IO[str]) -> int:
    return write_json(frame, out)


def _parquet(frame: pd.DataFrame, out: IO[bytes]) -> int:
    frame.to_parquet(out, index=False)
    return len(frame)


def _write_file(path: str, write: Callable[[IO[bytes]], int]) -> int:
    """Write ``path`` whole or not at all: into a new file beside it, which replaces it
    once written and synced, so that a failure (a full disk, a database error, ^C) leaves
    no partial file and an older file as it was. A UsageError naming the path and the
    cause if it cannot be written (a missing folder, no permission, a directory).

    A path that is neither a file nor a directory (``-o /dev/stdout``, a named pipe) is
    written in place: there is no file to replace, and replacing the device would be
    wrong. A symbolic link is followed: the file it points to is replaced."""
    target = Path(os.path.realpath(path))
    try:
        if target.is_dir():  # refused before the runs are read and written
            raise IsADirectoryError(errno.EISDIR, os.strerror(errno.EISDIR))
        if target.exists() and not target.is_file():
            with target.open("wb") as out:
                return write(out)
        return write_whole(target, write)
    except BrokenPipeError:  # -o /dev/stdout into `head`: main() handles it
        raise
    except OSError as exc:
        raise UsageError(f"--output: cannot write {terminal_safe(path)}: "
                         f"{exc.strerror or exc} (allowed: a file in an existing folder "
                         "you can write to)") from None
