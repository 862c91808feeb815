"""The arguments of ``slopetui rerun``."""

from __future__ import annotations

import argparse

from slopetui.cli.arguments import add_db_option


def declare(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("rerun", help="queue a stored run again with the certified stop",
                       description="Queue run ID again at its point, with its solver and "
                                   "history, and stop = certified (the run ends at the "
                                   "certificate of its attractor, or at t_end): a one-run "
                                   "sweep, as the application's certified re-run (u in the "
                                   "run detail) queues it. `slopetui show SWEEP` and `runs` "
                                   "show the result; a result already computed comes from "
                                   "the cache.")
    p.add_argument("id", metavar="ID", help="a run's id")
    p.add_argument("--json", action="store_true",
                   help='print one JSON object: {"sweep_id", "n_runs", "n_cached"}')
    add_db_option(p)
