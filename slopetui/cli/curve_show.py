"""``slopetui curve [ID]``: the stored curves in two parameters (``continue --param2
--submit`` queues them), or one of them with its points and codimension-two points."""

from __future__ import annotations

import argparse

from slopetui.cli.options import UsageError, int_arg, open_db
from slopetui.display_text import terminal_safe
from slopetui.json_text import json_text
from slopetui.provenance import computed_at
from slopetui.sweeps.curve_records import curve_solver, print_codim2, print_curve_point
from slopetui.sweeps.curves import CURVE_NAMES, curve_of, listing


def _listing(args: argparse.Namespace) -> int:
    stored = listing(open_db(args))
    if args.json:
        print(json_text({"curves": [c.summary() for c in stored]}))
        return 0
    if not stored:
        print("no curves yet: slopetui continue --help (--param2 ... --submit)")
        return 0
    print(f"{'id':>4}  {'kind':5} {'plane':12} {'status':9} {'points':>6}  end")
    for c in stored:
        row = c.row
        plane = f"({row.param}, {row.param2})"
        print(f"{c.id:>4}  {terminal_safe(row.kind):5} {terminal_safe(plane):12} "
              f"{terminal_safe(row.status):9} {row.n_points:>6}  "
              f"{terminal_safe(row.end_reason or '')}")  # stored text, escaped
    return 0


def _one(args: argparse.Namespace) -> int:
    curve = curve_of(open_db(args), args.id)
    if curve is None:
        raise UsageError(f"no curve {args.id} in this store (slopetui curve lists them)")
    row = curve.row
    name, second = terminal_safe(curve.param), terminal_safe(curve.second)
    if args.json:
        first = curve.points[0][curve.param] if curve.points else None
        print(json_text({**curve.summary(), "curve": curve.points,
                         "bifurcations": curve.bifurcations,
                         **computed_at(row, curve_solver(row.dt, row.kind, row.max_points, row.max_step,
                                                   row.end_value), row.engine,
                                       start=(curve.param, first))}))
        return 0
    what = CURVE_NAMES.get(str(row.kind), str(row.kind))
    print(f"curve {curve.id}: the {terminal_safe(what)} in ({name}, {second}): {terminal_safe(row.status)}, "
          f"{row.n_points} points, {row.runtime_s:.1f} s")
    for point in curve.points:
        print_curve_point(curve.param, curve.second, point)
    if row.status == "done":
        print(f"end: {terminal_safe(row.end_reason)}")
        print_codim2(curve.param, curve.second, curve.bifurcations)
    elif row.error:
        print(f"{terminal_safe(row.status)}: {terminal_safe(row.error.splitlines()[-1])}")
    return 0


def handle(args: argparse.Namespace) -> int:
    if args.id is not None:  # read as text: a one-line error, not argparse's usage
        args.id = int_arg("ID", args.id, 1, note=" (a curve id)")
        return _one(args)
    return _listing(args)
