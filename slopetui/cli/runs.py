"""``slopetui runs``: filter and list runs; ``slopetui export SWEEP --csv | --parquet |
--json``: a sweep's runs as a file (the formats: ``slopetui.sweeps.export`` for CSV,
``slopetui.sweeps.frames`` for the DataFrame that Parquet and JSON are written from)."""

from __future__ import annotations

import argparse
import errno
import io
import os
import sys
from collections.abc import Callable, Iterable
from contextlib import closing
from pathlib import Path
from typing import IO, TYPE_CHECKING

from slopetui.cli.options import UsageError, int_arg, open_db, sweep_arg
from slopetui.display_text import terminal_safe, terminal_safe_lines
from slopetui.whole_files import as_text, write_whole

if TYPE_CHECKING:
    import pandas as pd

    from slopetui.store.database import Database
    from slopetui.store.models import Run



def _num(x: float | None, fmt: str = ".4g") -> str:
    return "-" if x is None else format(x, fmt)


def csv_to_stdout(runs: Iterable[Run]) -> int:
    """The runs as CSV on stdout; returns how many (see text_to_stdout)."""
    return text_to_stdout(lambda out: _csv(runs, out))


def text_to_stdout(write: Callable[[IO[str]], int]) -> int:
    """What ``write`` writes (it returns how many runs), on stdout. Into a pipe or a file
    the text is as stored (it is data: a reader must get what the store holds); on a
    terminal, where a stored escape sequence would drive the reader's terminal, it goes
    through terminal_safe, newlines kept."""
    if not sys.stdout.isatty():
        return write(sys.stdout)
    buf = io.StringIO()
    n = write(buf)
    sys.stdout.write(terminal_safe_lines(buf.getvalue()))
    return n


def handle_runs(args: argparse.Namespace) -> int:
    limit = int_arg("--limit", args.limit, 0, note=" (0 for all)")
    sweep = None if args.sweep is None else sweep_arg(args.sweep, "--sweep")
    from slopetui.store.queries import runs_matching

    runs = runs_matching(open_db(args), sweep=sweep, regime=args.regime, status=args.status,
                         limit=limit)
    if args.csv:
        csv_to_stdout(runs)
        return 0
    if not runs:
        print("no runs match")
        return 0
    print(f"{'id':>6} {'sweep':>5} {'status':9} {'regime':12} {'k':>7} {'tau':>7} {'a':>6} "
          f"{'b':>6} {'c':>6} {'delta':>7} {'lambda_max':>10} {'amplitude':>9} {'period':>8}")
    for r in runs:
        done = r.status == "done" and not r.inferred  # an inferred run has no measurements
        status = "inferred" if r.inferred else terminal_safe(r.status)  # stored text
        regime = terminal_safe(r.regime or "-")
        print(f"{r.id:>6} {r.sweep_id:>5} {status:9} {regime:12} {r.k:>7.4g} "
              f"{r.tau:>7.4g} {r.a:>6.4g} {r.b:>6.4g} {r.c:>6.4g} {r.delta:>7.2g} "
              f"{_num(r.lambda_max if done else None, '.3g'):>10} "
              f"{_num(r.amplitude if done else None):>9} {_num(r.period if done else None):>8}")
    return 0


#: The one line of an export --parquet without pyarrow (an optional extra).
NO_PYARROW = "export --parquet needs pyarrow: pip install 'slopetui[parquet]'"


def handle_export(args: argparse.Namespace) -> int:
    from slopetui.store.queries import sweep_exists
    from slopetui.sweeps.control import UnknownSweep

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
    from slopetui.store.queries import runs_of

    with closing(runs_of(db, sweep)) as runs:
        if not output:
            return csv_to_stdout(runs)
        return _write_file(output, lambda out: as_text(out, lambda text: _csv(runs, text)))


def _export_frame(db: Database, sweep: int, form: str, output: str | None) -> int:
    """The sweep's runs as Parquet or JSON, from their DataFrame, to ``output`` or stdout."""
    from slopetui.sweeps.frames import runs_frame

    frame = runs_frame(db, sweep)
    if output:
        if form == "parquet":
            return _write_file(output, lambda out: _parquet(frame, out))
        return _write_file(output, lambda out: as_text(out, lambda text: _json(frame, text)))
    if form == "parquet":  # not a terminal: handle_export refused that
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


def _csv(runs: Iterable[Run], out: IO[str]) -> int:
    from slopetui.sweeps.export import write_csv
    return write_csv(runs, out)


def _json(frame: pd.DataFrame, out: IO[str]) -> int:
    from slopetui.sweeps.export_files import write_json
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
