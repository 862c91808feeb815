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
(slopetui.figures.output.write).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from slopetui.cli.options import UsageError, add_db_option, int_arg, open_db, sweep_arg
from slopetui.display_text import terminal_safe

if TYPE_CHECKING:
    from slopetui.figures.output import Drawing
    from slopetui.store.database import Database
    from slopetui.sweeps.recompute import StoredRun

#: Runs one comparison overlays at most: beyond this the lines are no longer told apart.
MAX_RUNS = 8
#: The formats, by extension (slopetui.figures.output.FORMATS; not imported: it loads
#: nothing heavy, but --help should not depend on it).
FORMATS_TEXT = ".pdf, .svg or .png"


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "figure", help="write a sweep's or runs' figure (PDF, SVG, PNG) with its data (CSV)",
        description="Draw a publication figure with matplotlib: a sweep's phase diagram (2-D) "
                    "or bifurcation diagram (1-D), or a run's time series, phase portrait, "
                    "spectrum and running λmax (recomputed), or several runs overlaid. Fonts are "
                    "embedded (TrueType), dense layers rasterised; the data of the figure is "
                    "written beside it as CSV (<name>.csv, <name>.<table>.csv). No display needed.",
        epilog="examples: slopetui figure 3 -o fig4.pdf · slopetui figure 3 --fold -o plane.png · "
               "slopetui figure --run 120 --run 121 -o compare.svg")
    p.add_argument("sweep", metavar="SWEEP", nargs="?", help="sweep id (or give --run)")
    p.add_argument("--run", metavar="RUN", action="append", default=[],
                   help=f"a run id; repeat to overlay up to {MAX_RUNS} runs")
    p.add_argument("-o", "--output", metavar="FILE",
                   help=f"the figure file, {FORMATS_TEXT} (default: sweep-N.pdf, run-N.pdf or "
                        "runs-N-M.pdf in the current folder)")
    p.add_argument("--no-hopf", dest="hopf", action="store_false",
                   help="do not draw the exact Hopf curve over a phase diagram")
    p.add_argument("--fold", action="store_true",
                   help="also draw the fold of cycles over a (k, tau), (a, tau), (b, tau) or "
                        "(c, tau) plane (continuation at each tau: seconds to minutes)")
    add_db_option(p)
    p.set_defaults(handler=handle)


def handle(args: argparse.Namespace) -> int:
    from slopetui.figures.figure_files import DEFAULT_FORMAT, runs_stem, sweep_stem
    from slopetui.figures.output import FigureError, check_output

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
        from slopetui.figures.output import write
        written = write(drawing, path)
    except FigureError as exc:  # the folder changed since the check: still nothing partial
        raise UsageError(str(exc)) from None
    _say_written(written)
    return 0


def _sweep_drawing(db: Database, sweep: int, *, hopf: bool, fold: bool) -> Drawing:
    from slopetui.cli.show import fold_curve_of
    from slopetui.figures.figure_files import sweep_figure
    from slopetui.sweeps.diagram import load_diagram

    diagram = load_diagram(db, sweep)  # UnknownSweep: exit 2, nothing written
    return sweep_figure(diagram, hopf=hopf, fold=fold_curve_of(diagram.spec) if fold else None)


def _runs_drawing(db: Database, run_ids: list[int]) -> Drawing:
    from slopetui.figures.figure_files import runs_figure
    from slopetui.sweeps.recompute import load_run

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
