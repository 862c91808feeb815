"""``slopetui runs``: filter and list runs; ``slopetui export SWEEP --csv``."""

from __future__ import annotations

import argparse
import io
import sys
from collections.abc import Iterable
from contextlib import closing
from pathlib import Path
from typing import TYPE_CHECKING

from core.regimes import REGIMES
from slopetui.cli.options import UsageError, add_db_option, int_arg, open_db, sweep_arg
from slopetui.display_text import terminal_safe, terminal_safe_lines
from slopetui.store.statuses import RUN_STATUSES

if TYPE_CHECKING:
    from slopetui.store.models import Run


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("runs", help="list runs, filtered",
                       description="List runs, newest first. For anything richer: slopetui sql.")
    p.add_argument("--sweep", metavar="SWEEP", help="only this sweep (its id)")
    p.add_argument("--regime", choices=REGIMES, help="only this regime")
    p.add_argument("--status", choices=RUN_STATUSES, help="only this status")
    p.add_argument("--limit", default="50", metavar="N",
                   help="at most N runs (default 50; 0 for all)")
    p.add_argument("--csv", action="store_true", help="CSV with every column")
    add_db_option(p)
    p.set_defaults(handler=handle_runs)

    e = sub.add_parser("export", help="write a sweep's runs as CSV",
                       description="Every column of every run of the sweep, in grid order. "
                                   "NaN and infinity are written as nan, inf, -inf. Text is "
                                   "written as stored, except on a terminal, where control "
                                   "characters are shown escaped (\\x1b).")
    e.add_argument("sweep", metavar="SWEEP", help="sweep id")
    e.add_argument("--csv", action="store_true", required=True, help="CSV (the only format)")
    e.add_argument("-o", "--output", metavar="FILE", help="write to FILE instead of stdout")
    add_db_option(e)
    e.set_defaults(handler=handle_export)


def _num(x: float | None, fmt: str = ".4g") -> str:
    return "-" if x is None else format(x, fmt)


def csv_to_stdout(runs: Iterable[Run]) -> int:
    """The runs as CSV on stdout; returns how many. Into a pipe or a file the text is as
    stored (it is data: a reader must get what the store holds); on a terminal, where a
    stored escape sequence would drive the reader's terminal, it goes through
    terminal_safe, newlines kept."""
    from slopetui.sweeps.export import write_csv

    if not sys.stdout.isatty():
        return write_csv(runs, sys.stdout)
    buf = io.StringIO()
    n = write_csv(runs, buf)
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


def handle_export(args: argparse.Namespace) -> int:
    from slopetui.store.queries import runs_of, sweep_exists
    from slopetui.sweeps.control import UnknownSweep

    sweep = sweep_arg(args.sweep)
    db = open_db(args)
    if not sweep_exists(db, sweep):
        raise UnknownSweep(sweep)
    with closing(runs_of(db, sweep)) as runs:
        if args.output:
            n = _write_file(args.output, runs)
            print(f"{n} runs of sweep {sweep} written to {terminal_safe(args.output)}",
                  file=sys.stderr)
        else:
            csv_to_stdout(runs)
    return 0


def _write_file(path: str, runs: Iterable[Run]) -> int:
    """Write the CSV to ``path``; a UsageError naming it and the cause if it cannot be
    written (a missing folder, no permission, a directory, a full disk)."""
    from slopetui.sweeps.export import write_csv

    try:
        with Path(path).open("w", encoding="utf-8", newline="") as out:
            return write_csv(runs, out)
    except BrokenPipeError:  # -o /dev/stdout into `head`: main() handles it
        raise
    except OSError as exc:
        raise UsageError(f"--output: cannot write {terminal_safe(path)}: "
                         f"{exc.strerror or exc} (allowed: a file in an existing folder "
                         "you can write to)") from None
