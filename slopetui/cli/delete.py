"""``slopetui delete SWEEP [--yes]``: delete a sweep and its runs, asking first.

Nothing undoes a delete, so it asks on a terminal ("delete sweep 5 '(k, tau) plane' and
its 1,200 runs? [y/N]", no unless y) and, with no terminal to ask on (a script, a pipe),
refuses unless --yes says the question was answered: a script that forgot --yes must not
delete. A sweep with running runs is refused either way (``sweeps.control.delete``):
cancel it, wait for its running runs, then delete it. Runs of other sweeps that copied
their results from its runs keep them.
"""

from __future__ import annotations

import argparse
import sys

from slopetui.cli.options import UsageError, open_db, sweep_arg
from slopetui.display_text import terminal_safe
from slopetui.sweeps import control
from slopetui.sweeps.progress import sweep_progress


def handle(args: argparse.Namespace) -> int:
    sweep = sweep_arg(args.sweep)  # before the database opens
    db = open_db(args)
    found = sweep_progress(db, [sweep])
    if not found:
        raise control.UnknownSweep(sweep)
    p = found[0]
    if p.running:  # the store refuses too (in its transaction): asking first would be idle
        raise UsageError(str(control.SweepBusy(sweep, p.running, p.status)))
    if not args.yes:
        if sys.stdin is None or not sys.stdin.isatty():
            raise UsageError(f"stdin is not a terminal, so there is no one to ask: pass "
                             f"--yes to delete sweep {sweep} and its runs")
        n = sum(p.counts.values())
        question = (f"delete sweep {sweep} '{terminal_safe(p.name)}' and its {n:,} "
                    f"{'run' if n == 1 else 'runs'}? [y/N] ")
        try:
            answer = input(question)
        except EOFError:  # Ctrl-D: no
            answer = ""
        if answer.strip().lower() not in ("y", "yes"):
            print(f"sweep {sweep} kept")
            return 1
    try:
        print(control.apply(db, "delete", sweep))
    except control.SweepBusy as exc:  # a run was claimed since the check above
        raise UsageError(str(exc)) from None
    return 0
