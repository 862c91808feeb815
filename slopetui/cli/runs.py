"""``slopetui runs``: filter and list runs (as a table, or as CSV: ``slopetui.sweeps.export``)."""

from __future__ import annotations

import argparse
import io
import sys
from collections.abc import Callable, Iterable
from typing import IO, TYPE_CHECKING

from slopetui.cli.options import int_arg, open_db, sweep_arg
from slopetui.display_text import terminal_safe, terminal_safe_lines
from slopetui.store.queries import runs_matching
from slopetui.sweeps.annotations import check_tag

if TYPE_CHECKING:

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
    tag = None if args.tag is None else check_tag(args.tag, "--tag")

    runs = runs_matching(open_db(args), sweep=sweep, regime=args.regime, status=args.status,
                         tag=tag, limit=limit)
    if args.csv:
        csv_to_stdout(runs)
        return 0
    if not runs:
        print("no runs match")
        return 0
    print(f"{'id':>6} {'sweep':>5} {'status':9} {'regime':12} {'k':>7} {'tau':>7} {'a':>6} "
          f"{'b':>6} {'c':>6} {'delta':>7} {'lambda_max':>10} {'amplitude':>9} {'period':>8} "
          f"{'stop':9} {'t_stop':>8}")
    for r in runs:
        done = r.status == "done" and not r.inferred  # an inferred run has no measurements
        status = "inferred" if r.inferred else terminal_safe(r.status)  # stored text
        regime = terminal_safe(r.regime or "-")
        print(f"{r.id:>6} {r.sweep_id:>5} {status:9} {regime:12} {r.k:>7.4g} "
              f"{r.tau:>7.4g} {r.a:>6.4g} {r.b:>6.4g} {r.c:>6.4g} {r.delta:>7.2g} "
              f"{_num(r.lambda_max if done else None, '.3g'):>10} "
              f"{_num(r.amplitude if done else None):>9} {_num(r.period if done else None):>8} "
              f"{terminal_safe(r.stop):9} {_num(r.t_stop if done else None, '.4g'):>8}")
    return 0


def _csv(runs: Iterable[Run], out: IO[str]) -> int:
    # here: slopetui.sweeps.export loads numpy, which `runs` without --csv never needs
    from slopetui.sweeps.export import write_csv
    return write_csv(runs, out)
