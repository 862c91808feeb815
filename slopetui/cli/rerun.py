"""``slopetui rerun ID``: a stored run queued again with the certified stop
(slopetui.sweeps.certified_rerun, the application's certified re-run)."""

from __future__ import annotations

import argparse

from slopetui.cli.options import int_arg, open_db
from slopetui.json_text import json_text
from slopetui.sweeps.certified_rerun import rerun_certified


def handle(args: argparse.Namespace) -> int:
    run_id = int_arg("ID", args.id, 1, note=" (a run id)")
    out = rerun_certified(open_db(args), run_id)
    if args.json:
        print(json_text({"sweep_id": out.sweep_id, "n_runs": out.n_runs,
                         "n_cached": out.n_cached}))
        return 0
    cached = " (already computed: taken from the cache)" if out.n_cached else ""
    print(f"run {run_id} again with stop = certified: sweep {out.sweep_id}, "
          f"{out.n_runs} run queued{cached}")
    print(f"watch it: slopetui status; its result: slopetui runs --sweep {out.sweep_id}")
    return 0
