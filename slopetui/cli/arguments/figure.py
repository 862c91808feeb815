"""The arguments of ``slopetui figure``."""

from __future__ import annotations

import argparse

from slopetui.cli.arguments import add_db_option

#: Runs one comparison overlays at most: beyond this the lines are no longer told apart.
MAX_RUNS = 8

#: The formats, by extension (slopetui.figures.output.FORMATS; not imported: it loads
#: nothing heavy, but --help should not depend on it).
FORMATS_TEXT = ".pdf, .svg or .png"


def declare(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "figure", help="write a sweep's or runs' figure (PDF, SVG, PNG) with its data (CSV)",
        description="Draw a publication figure with matplotlib: a sweep's phase diagram (2-D) "
                    "or bifurcation diagram (1-D), or a run's time series, phase portrait, "
                    "spectrum and running λmax (recomputed), or several runs overlaid. Fonts are "
                    "embedded (TrueType), dense layers rasterised; the data of the figure is "
                    "written beside it as CSV (<name>.csv, <name>.<table>.csv), whose first "
                    "line is '# slopetui: {...}', what it was computed at (JSON), before the "
                    "header: read it with pandas.read_csv(path, skiprows=1). No display needed.",
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
    p.add_argument("--caption", action="store_true",
                   help="add a caption under the figure naming what it was computed at "
                        "(parameters; solver and engine); the file's metadata and the CSV's "
                        "first line name them always")
    add_db_option(p)
