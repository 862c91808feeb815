"""``slopetui show SWEEP``: the sweep's diagram on stdout.

A 2-D sweep draws its phase diagram (one colour and marker per regime, the exact Hopf
curve of ``core.stability`` over it where the plane has one); a 1-D sweep draws its
bifurcation diagram (the peak clusters of m_y against the parameter, as in Fig. 4A).
Runs that are not finished yet are drawn as pending; sliding runs of a bifurcation
diagram at their mean m_y (near the fixed point m_y = 0). An adaptive phase diagram is
drawn like any other: inferred runs in their regime's style, lattice points of levels
not queued yet as pending, and "N computed, M inferred" in the legend.
"""

from __future__ import annotations

import argparse
import os
import shutil
import sys

from sqlalchemy import func, select

from slopetui.cli.options import UsageError, add_db_option, open_db, sweep_id
from slopetui.plots import render_bifurcation, render_phase_diagram
from slopetui.store.database import Database
from slopetui.store.models import Sweep
from slopetui.sweeps.diagram import SweepDiagram, load_diagram, plane_hopf


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("show", help="draw a sweep's phase or bifurcation diagram",
                       description="Draw the sweep's phase diagram (2-D) or bifurcation "
                                   "diagram (1-D) in the terminal.")
    p.add_argument("sweep", type=sweep_id, metavar="SWEEP", nargs="?",
                   help="sweep id (default: the newest sweep)")
    p.add_argument("--width", type=int, help="columns (default: the terminal's)")
    p.add_argument("--height", type=int, help="lines (default: the terminal's, at most 40)")
    p.add_argument("--color", choices=("auto", "always", "never"), default="auto",
                   help="auto: colour on a terminal unless NO_COLOR is set")
    p.add_argument("--no-hopf", dest="hopf", action="store_false",
                   help="do not draw the exact Hopf curve")
    add_db_option(p)
    p.set_defaults(handler=handle)


def use_color(choice: str) -> bool:
    if choice != "auto":
        return choice == "always"
    return sys.stdout.isatty() and not os.environ.get("NO_COLOR")


def handle(args: argparse.Namespace) -> int:
    size = shutil.get_terminal_size((100, 30))
    width = args.width or size.columns
    height = args.height or min(size.lines - 1, 40)
    if width < 30 or height < 12:
        raise UsageError(f"the diagram needs --width >= 30 and --height >= 12, "
                         f"got {width} x {height}")
    db = open_db(args)
    if args.sweep is None:
        args.sweep = newest_sweep(db)
    diagram = load_diagram(db, args.sweep)
    spec, runs = diagram.spec, diagram.runs
    title = f"sweep {diagram.id}: {diagram.name} ({diagram.n_done}/{diagram.n_points} done)"
    color = use_color(args.color)
    x = spec.x
    xs = [r.x for r in runs]
    regimes = [r.regime for r in runs]
    if spec.y is None:
        print(render_bifurcation(x.param, xs, [r.peaks for r in runs], regimes,
                                 log=x.spacing == "log", title=title, width=width,
                                 height=height, color=color))
        return 0
    y = spec.y
    ys = [r.y for r in runs]
    for _, _, px, py in diagram.unqueued():  # an adaptive sweep's levels still to come
        xs.append(px)
        ys.append(py)
        regimes.append(None)
    hopf = plane_hopf(spec) if args.hopf else None
    print(render_phase_diagram(x.param, y.param, xs, ys, regimes,
                               x_log=x.spacing == "log", y_log=y.spacing == "log", hopf=hopf,
                               title=title, width=width, height=height, color=color,
                               notes=adaptive_notes(diagram)))
    return 0


def adaptive_notes(diagram: SweepDiagram) -> list[str]:
    """The legend's line on an adaptive sweep: how much of it was computed."""
    levels = diagram.spec.adaptive_levels
    if levels is None:
        return []
    counts = f"{diagram.n_computed} computed, {diagram.n_inferred} inferred"
    return [f"{counts} (adaptive, {levels} levels)"]


def newest_sweep(db: Database) -> int:
    with db.sessions() as s:
        newest = s.scalar(select(func.max(Sweep.id)))
    if newest is None:
        raise UsageError("there are no sweeps yet: slopetui submit --help")
    return newest
