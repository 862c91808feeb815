"""``slopetui show SWEEP``: the sweep's diagram on stdout.

A 2-D sweep draws its phase diagram, a 1-D sweep its bifurcation diagram, through the
one render path of every face (``slopetui.plots.sweep_diagram.render_sweep``, which says
what is drawn: pending runs, an adaptive sweep's points to come and its legend line).
"""

from __future__ import annotations

import argparse
import os
import shutil
import sys
from typing import TYPE_CHECKING

from slopetui.cli.arguments.show import MAX_SIZE, MIN_HEIGHT, MIN_WIDTH
from slopetui.cli.options import UsageError, int_arg, sweep_arg
from slopetui.plots import render_sweep
from slopetui.sweeps.diagram import load_drawing

if TYPE_CHECKING:
    from slopetui.sweeps.fold_overlay import Curve
    from slopetui.sweeps.spec import SweepSpec


def use_color(choice: str) -> bool:
    if choice != "auto":
        return choice == "always"
    return sys.stdout.isatty() and not os.environ.get("NO_COLOR")


def handle(args: argparse.Namespace) -> int:
    size = shutil.get_terminal_size((100, 30))
    width = (int_arg("--width", args.width, MIN_WIDTH, MAX_SIZE) if args.width is not None
             else min(size.columns, MAX_SIZE))
    height = (int_arg("--height", args.height, MIN_HEIGHT, MAX_SIZE) if args.height is not None
              else min(size.lines - 1, 40))
    if width < MIN_WIDTH or height < MIN_HEIGHT:  # a small terminal, no --width/--height
        raise UsageError(f"the diagram needs --width >= {MIN_WIDTH} and --height >= "
                         f"{MIN_HEIGHT}; this terminal gives {width} x {height}")
    sweep = sweep_arg(args.sweep) if args.sweep is not None else None
    # without the measurements a drawing does not show (half the read of a 10,000-run
    # sweep), and from a SQLite file without SQLAlchemy (0.35-0.45 s of start-up)
    diagram = load_drawing(args.db, sweep,
                           say=lambda note: print(f"slopetui show: {note}", file=sys.stderr))
    if diagram is None:
        raise UsageError("there are no sweeps yet: slopetui submit --help")
    fold = fold_curve_of(diagram.spec) if args.fold else None
    print(render_sweep(diagram, width=width, height=height, color=use_color(args.color),
                       hopf=args.hopf, fold=fold))
    return 0


def fold_curve_of(spec: SweepSpec) -> Curve | None:
    """The sweep's fold curve, with a line on stderr per tau (it takes a while)."""
    # here: the continuation loads numba's kernels, which `show` without --fold never needs
    from slopetui.sweeps.fold_overlay import fold_overlay, has_fold_plane
    if not has_fold_plane(spec):
        raise UsageError("--fold draws over a (k, tau), (a, tau), (b, tau) or (c, tau) phase "
                         "diagram only; this sweep is not one")
    name = spec.x.param

    def say(tau: float, fold: float | None) -> None:
        found = f"{name} = {fold:.5g}" if fold is not None else "none (supercritical Hopf point)"
        print(f"fold of cycles at tau = {tau:.4g}: {found}", file=sys.stderr, flush=True)

    return fold_overlay(spec, say)

