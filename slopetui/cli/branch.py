"""``slopetui branch [ID]``: the stored continuations (``continue --submit`` queues them),
or one of them with its points, its bifurcations and, with ``--plot``, its diagram."""

from __future__ import annotations

import argparse
import shutil
from typing import TYPE_CHECKING

from slopetui.cli.branch_lines import print_bifurcations, print_point
from slopetui.cli.options import UsageError, int_arg, open_db
from slopetui.display_text import terminal_safe
from slopetui.json_text import json_text
from slopetui.plots.branch_plot import render_branch
from slopetui.provenance import computed_at
from slopetui.sweeps.branches import branch_of, listing, start_name

if TYPE_CHECKING:
    from slopetui.sweeps.branches import StoredBranch



def _found(branch: StoredBranch) -> str:
    if branch.bifurcations:
        return ", ".join(f"{terminal_safe(b['type'])} {terminal_safe(branch.param)}={b['value']:.6g}"
                         for b in branch.bifurcations)
    return "none" if branch.row.status == "done" else ""


def _listing(args: argparse.Namespace) -> int:
    branches = listing(open_db(args))
    if args.json:
        print(json_text({"continuations": [b.summary() for b in branches]}))
        return 0
    if not branches:
        print("no continuations yet: slopetui continue --help (with --submit)")
        return 0
    print(f"{'id':>4}  {'param':5} {'start':14} {'status':9} {'points':>6}  found")
    for b in branches:
        row = b.row
        start = f"{start_name(row)} tau={row.tau:g}" if b.param != "tau" else \
            f"{start_name(row)} k={row.k:g}"
        print(f"{b.id:>4}  {terminal_safe(b.param):5} {terminal_safe(start):14} {terminal_safe(row.status):9} "
              f"{row.n_points:>6}  {_found(b)}")  # stored text, escaped
    return 0


def _start_value(branch: StoredBranch) -> float | None:
    """Where the branch starts in its parameter: the Hopf point (None until its first point
    is saved), or the first point (a simulated orbit: the stored value until then)."""
    row = branch.row
    if row.start == "hopf":
        return row.hopf_value
    return branch.points[0]["value"] if branch.points else float(getattr(row, branch.param))


def _one(args: argparse.Namespace) -> int:
    branch = branch_of(open_db(args), args.id)
    if branch is None:
        raise UsageError(f"no continuation {args.id} in this store (slopetui branch lists them)")
    row = branch.row
    param = terminal_safe(branch.param)  # stored text, as every other text printed below
    if args.json:
        print(json_text({**branch.summary(), "branch": branch.points,
                         "bifurcations": branch.bifurcations,
                         # as `continue --json` says it; the engine it was computed with
                         **computed_at(row, {"method": "rk4", "dt": row.dt,
                                             "from_hopf": row.start == "hopf",
                                             "points": row.max_points, "max_step": row.max_step},
                                       row.engine, start=(branch.param, _start_value(branch)))}))
        return 0
    if args.plot:
        size = shutil.get_terminal_size((100, 30))
        print(render_branch(branch.param, branch.points, branch.bifurcations,
                            title=f"continuation {branch.id} in {branch.param}",
                            width=size.columns, height=max(size.lines - 2, 12)))
        return 0
    hopf = f"Hopf point {row.hopf_branch}"  # the n-th, as `continue` names it
    print(f"continuation {branch.id} in {param} from "
          f"{hopf if row.start == 'hopf' else 'a simulated orbit'}: "
          f"{terminal_safe(row.status)}, {row.n_points} points, {row.runtime_s:.1f} s")
    for point in branch.points:
        print_point(param, point)
    if row.hopf_value is not None:
        print(f"{hopf}: {param} = {row.hopf_value:.10g}, period "
              f"{row.hopf_period:.10g}" + (f"; {terminal_safe(row.criticality)}"
                                              if row.criticality else "")
              + (f" (l1 = {row.l1:.6g})" if row.l1 is not None else ""))
    if row.status == "done":
        print(f"end: {terminal_safe(row.end_reason)}")
        print_bifurcations(param, branch.bifurcations)
    elif row.error:
        print(f"{terminal_safe(row.status)}: {terminal_safe(row.error.splitlines()[-1])}")
    return 0


def handle(args: argparse.Namespace) -> int:
    if args.plot and args.id is None:
        raise UsageError("--plot draws one continuation: give its ID")
    if args.id is not None:  # read as text: a one-line error, not argparse's usage or SQL's overflow
        args.id = int_arg("ID", args.id, 1, note=" (a continuation id)")
    return _listing(args) if args.id is None else _one(args)
