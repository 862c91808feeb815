"""``slopetui submit``: queue a sweep from a TOML spec file and/or flags."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Mapping
from typing import Any

from core.params import PARAM_NAMES
from slopetui.cli.options import open_db
from slopetui.json_text import json_text
from slopetui.sweeps.sizes import CONFIRM_ABOVE_RUNS
from slopetui.sweeps.spec import SpecError, parse_axis_flag, parse_spec, read_spec, with_stop
from slopetui.sweeps.submit import submit


def _merge(data: dict[str, Any], key: str, flags: Mapping[str, Any]) -> None:
    """Put the flags' values over the file's table ``key``. A file whose ``key`` is not a
    table (``solver = [1]``) is left as it is, for parse_spec to name."""
    table = data.get(key)
    if table is not None and not isinstance(table, Mapping):
        return
    merged = {**(table or {}), **flags}
    if merged:
        data[key] = merged


def _condition(i: int, text: str) -> dict[str, Any]:
    """One --initial: comma-separated key=value pairs (delta, history)."""
    out: dict[str, Any] = {}
    for part in text.split(","):
        key, sep, value = part.partition("=")
        if not sep or key.strip() not in ("delta", "history"):
            raise SpecError(f"initial[{i}]", f"expected delta=X and/or history=H separated "
                                             f"by commas, got {text!r}")
        out[key.strip()] = value.strip()
    return out


def spec_data(args: argparse.Namespace) -> dict[str, Any]:
    """The spec as a mapping: the file's tables, then the flags on top; the stop rule is
    --stop, else the file's, else a new sweep's default (spec.with_stop)."""
    data = read_spec(args.spec) if args.spec else {}
    if args.x:
        data["x"] = parse_axis_flag("--x", args.x)
    if args.y:
        data["y"] = parse_axis_flag("--y", args.y)
    if args.name:
        data["name"] = args.name
    if args.adaptive is not None:
        data["adaptive"] = {"levels": args.adaptive}
    _merge(data, "fixed", {n: getattr(args, f"fixed_{n}") for n in PARAM_NAMES
                           if getattr(args, f"fixed_{n}") is not None})
    _merge(data, "solver", {k: getattr(args, k)
                            for k in ("method", "dt", "t_end", "window", "lyap", "history")
                            if getattr(args, k) is not None})
    if args.initial:
        data["initial"] = [_condition(i, text) for i, text in enumerate(args.initial)]
    if "x" not in data:
        raise SpecError("x", "missing: give a SPEC.toml file or --x PARAM=START:STOP:NUM")
    return with_stop(data, args.stop)


def handle(args: argparse.Namespace) -> int:
    # every check happens before the database opens, the admission checks of a new sweep
    # (the engine's limits, the name's characters) included
    spec = parse_spec(spec_data(args), submitting=True)
    if spec.first_runs > CONFIRM_ABOVE_RUNS and not args.yes:
        what = (f"{spec.first_runs} coarse runs (of a {spec.n_runs}-point lattice)"
                if spec.adaptive_levels is not None else f"{spec.n_runs} runs")
        print(f"slopetui submit: this sweep would queue {what} (more than "
              f"{CONFIRM_ABOVE_RUNS}); add --yes to queue it", file=sys.stderr)
        return 2
    db = open_db(args)

    out = submit(db, spec)
    if args.json:
        data = {"sweep_id": out.sweep_id, "n_runs": out.n_runs, "n_cached": out.n_cached}
        if out.adaptive_levels is not None:  # n_runs: the coarse runs; n_points: the lattice
            data.update(n_points=out.n_points, adaptive_levels=out.adaptive_levels)
        print(json_text(data))
    else:
        cached = f" ({out.n_cached} already computed, taken from the cache)" if out.n_cached else ""
        if out.adaptive_levels is None:
            print(f"sweep {out.sweep_id}: {out.n_runs} runs queued{cached}")
        else:
            assert spec.y is not None
            print(f"sweep {out.sweep_id}: adaptive, {out.n_runs} coarse runs queued{cached}; "
                  f"refined up to {out.adaptive_levels} levels to the {spec.x.num} x "
                  f"{spec.y.num} lattice as they finish")
        print(f"watch it: slopetui status; draw it: slopetui show {out.sweep_id}")
    return 0
