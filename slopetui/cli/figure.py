"""``slopetui figure SWEEP`` and ``slopetui figure --run ID [--run ID ...]``: publication
figures drawn with matplotlib into a PDF, SVG or PNG file, their data as CSV beside them.

A sweep gives its phase diagram (2-D: one colour per regime, the exact Hopf curve, the
fold of cycles with --fold) or its bifurcation diagram (1-D); one run gives its time
series, phase portrait, spectrum and running λmax (recomputed, as the run detail does);
several runs are overlaid. No display is needed (matplotlib's Figure without pyplot:
Agg, PDF and SVG canvases), so it works over SSH.

Everything the user typed is checked before anything is computed or written: the output
path (extension, folder), the sweep or the runs (they exist), so a recomputation of
minutes never ends in "cannot write". The files appear whole or not at all
(slopetui.figures.output.write). Each names what it was computed at (parameters, solver,
engine): the figure in its metadata, each CSV in a comment line before its header, and,
with --caption, a line under the figure (slopetui.figures.figure_facts).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from slopetui.cli.arguments.figure import FORMATS_TEXT, MAX_RUNS
from slopetui.cli.options import UsageError, int_arg, open_db, sweep_arg
from slopetui.cli.show import fold_curve_of
from slopetui.display_text import terminal_safe
from slopetui.figures.figure_files import DEFAULT_FORMAT, runs_figure, runs_stem, sweep_figure, sweep_stem
from slopetui.figures.output import FigureError, check_output, write
from slopetui.store.queries import sweep_engines
from slopetui.sweeps.diagram import load_diagram
from slopetui.sweeps.recompute import load_run

if TYPE_CHECKING:
    from slopetui.figures.output import Drawing
    from slopetui.store.database import Database
    from slopetui.sweeps.recompute import StoredRun


def handle(args: argparse.Namespace) -> int:
    if (args.sweep is None) == (not args.run):
        raise UsageError("give a SWEEP or one or more --run RUN (not both)")
    if args.run and (args.fold or not args.hopf):
        raise UsageError("--fold and --no-hopf apply to a sweep's figure, not to --run")
    if len(args.run) > MAX_RUNS:
        raise UsageError(f"--run is given {len(args.run)} times: allowed 1 to {MAX_RUNS} runs")
    sweep = sweep_arg(args.sweep) if args.sweep is not None else None
    run_ids = [int_arg("--run", text, 1, note=" (a run id)") for text in args.run]
    if len(set(run_ids)) < len(run_ids):
        raise UsageError("--run names the same run twice")
    default = sweep_stem(sweep) if sweep is not None else runs_stem(run_ids)
    if args.output is not None and not args.output.strip():  # before: the default name
        raise UsageError(f"--output = {args.output!r} is empty: allowed a file name ending "
                         f"in {FORMATS_TEXT}")
    try:
        path = check_output(args.output if args.output is not None else f"{default}.{DEFAULT_FORMAT}")
    except FigureError as exc:
        raise UsageError(str(exc)) from None
    db = open_db(args)
    if sweep is not None:
        drawing = _sweep_drawing(db, sweep, hopf=args.hopf, fold=args.fold)
    else:
        drawing = _runs_drawing(db, run_ids)
    try:
        written = write(drawing, path, caption=args.caption)
    except FigureError as exc:  # the folder changed since the check: still nothing partial
        raise UsageError(str(exc)) from None
    _say_written(written)
    return 0


def _sweep_drawing(db: Database, sweep: int, *, hopf: bool, fold: bool) -> Drawing:
    diagram = load_diagram(db, sweep)  # UnknownSweep: exit 2, nothing written
    return sweep_figure(diagram, hopf=hopf, fold=fold_curve_of(diagram.spec) if fold else None,
                        engines=sweep_engines(db, sweep))


def _runs_drawing(db: Database, run_ids: list[int]) -> Drawing:
    runs = []
    for run_id in run_ids:
        run = load_run(db, run_id)
        if run is None:
            raise UsageError(f"--run {run_id}: there is no such run in this store")
        run.inputs()  # a run whose stored inputs are invalid: ParameterError before any work
        runs.append(run)

    def say(run: StoredRun) -> None:
        took = run.runtime_s  # NaN for a run never computed
        about = f", about {took:.0f} s" if took is not None and took >= 1 else ""
        print(f"recomputing run {run.id} (t_end = {run.t_end:g}{about})", file=sys.stderr, flush=True)

    return runs_figure(runs, say)


def _say_written(paths: list[Path]) -> None:
    figure, *data = paths
    print(f"figure written to {terminal_safe(str(figure))}")
    for p in data:
        print(f"its data: {terminal_safe(str(p))}")
