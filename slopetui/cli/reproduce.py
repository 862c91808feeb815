"""``slopetui reproduce``: the paper's figures as sweeps, and the reproduction report."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from slopetui.cli.arguments.reproduce import REPORT_RESOLUTION
from slopetui.cli.options import UsageError, open_db
from slopetui.reproduce.report import write_report
from slopetui.sweeps.presets import BY_KEY, PRESETS
from slopetui.sweeps.sizes import CONFIRM_ABOVE_RUNS
from slopetui.sweeps.spec import parse_spec
from slopetui.sweeps.submit import submit


def preset_specs(keys: list[str], resolution: int | None, t_end: float | None) -> list:
    return [parse_spec(BY_KEY[k].at_resolution(resolution, t_end)) for k in keys]


def _check(args: argparse.Namespace) -> list[str]:
    if args.resolution is not None and not 2 <= args.resolution <= 500:
        raise UsageError(f"--resolution must be in 2..500, got {args.resolution}")
    if args.t_end is not None and not args.t_end > 0:
        raise UsageError(f"--t-end must be > 0, got {args.t_end}")
    if args.report or args.figure == "all":
        return [p.key for p in PRESETS]
    if args.figure is None:
        raise UsageError("give a FIG (see --list), 'all', --list or --report")
    if args.figure not in BY_KEY:
        raise UsageError(f"FIG: unknown figure {args.figure!r}; one of "
                         + ", ".join(BY_KEY) + " or all")
    return [args.figure]


def handle(args: argparse.Namespace) -> int:
    if args.list:
        for p in PRESETS:
            spec = parse_spec(p.spec)
            print(f"{p.key:7} {p.figure:9} {p.title}  [{spec.n_runs} runs at full resolution]")
        return 0
    keys = _check(args)
    if args.report:
        resolution = args.resolution or REPORT_RESOLUTION
        path, complete = write_report(open_db(args), resolution, args.t_end, Path(args.out),
                                      args.jobs, args.orbits, say=progress_line)
        if not complete:
            print(f"report written to {path}, marked INCOMPLETE: some figures have runs "
                  "missing and no verdict; run the same command again to finish")
            return 1
        print(f"report written to {path}")
        return 0
    specs = preset_specs(keys, args.resolution, args.t_end)
    total = sum(s.n_runs for s in specs)
    if total > CONFIRM_ABOVE_RUNS and not args.yes:
        raise UsageError(f"this would queue {total} runs (more than {CONFIRM_ABOVE_RUNS}); add "
                         "--yes, or lower --resolution")

    db = open_db(args)
    for key, spec in zip(keys, specs, strict=True):
        out = submit(db, spec)
        cached = f" ({out.n_cached} from the cache)" if out.n_cached else ""
        print(f"{key}: sweep {out.sweep_id}, {out.n_runs} runs queued{cached}")
    return 0


def progress_line(text: str) -> None:
    """A step of the report's continuation analysis, on stderr (minutes pass between the
    pool's last line and the report)."""
    print(f"reproduce: {text}", file=sys.stderr, flush=True)
