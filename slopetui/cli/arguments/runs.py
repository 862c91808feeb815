"""The arguments of ``slopetui runs`` and ``slopetui export``."""

from __future__ import annotations

import argparse

from core.regimes import REGIMES
from slopetui.cli.arguments import add_db_option
from slopetui.store.statuses import RUN_STATUSES


def declare(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("runs", help="list runs, filtered",
                       description="List runs, newest first. For anything richer: slopetui sql.")
    p.add_argument("--sweep", metavar="SWEEP", help="only this sweep (its id)")
    p.add_argument("--regime", choices=REGIMES, help="only this regime")
    p.add_argument("--status", choices=RUN_STATUSES, help="only this status")
    p.add_argument("--tag", metavar="TAG", help="only the runs of sweeps with this tag "
                                                "(slopetui tag)")
    p.add_argument("--limit", default="50", metavar="N",
                   help="at most N runs (default 50; 0 for all)")
    p.add_argument("--csv", action="store_true", help="CSV with every column")
    add_db_option(p)

    e = sub.add_parser("export", help="write a sweep's runs as CSV, Parquet or JSON",
                       description="Every column of every run of the sweep, in grid order, "
                                   "in one of three formats. --csv: NaN and infinity are "
                                   "written as nan, inf, -inf; a value that does not exist "
                                   "(a result of a run that is not done) is an empty cell. "
                                   "--parquet: the DataFrame of slopetui.open_store(url)"
                                   ".runs(SWEEP) (needs pyarrow: pip install "
                                   "'slopetui[parquet]'); binary, so to -o FILE or into a "
                                   "pipe, never a terminal. --json: strict JSON, a list of one "
                                   "object per run with the CSV's columns as keys; NaN and "
                                   "infinity as the strings \"nan\", \"inf\", \"-inf\", "
                                   "a value that does not exist as null, peaks as an array, "
                                   "times in ISO 8601. Text is written as stored, except on a "
                                   "terminal, where control characters are shown escaped "
                                   "(\\x1b). A file is written whole or not at all.")
    e.add_argument("sweep", metavar="SWEEP", help="sweep id")
    formats = e.add_mutually_exclusive_group(required=True)
    formats.add_argument("--csv", dest="format", action="store_const", const="csv",
                         help="CSV, one line per run")
    formats.add_argument("--parquet", dest="format", action="store_const", const="parquet",
                         help="Parquet (needs pyarrow)")
    formats.add_argument("--json", dest="format", action="store_const", const="json",
                         help="JSON, a list of one object per run")
    e.add_argument("-o", "--output", metavar="FILE", help="write to FILE instead of stdout")
    add_db_option(e)
