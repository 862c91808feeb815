"""The arguments of ``slopetui sql``."""

from __future__ import annotations

import argparse

from slopetui.cli.arguments import add_db_option
from slopetui.store.read_query import DEFAULT_TIMEOUT_S


def declare(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("sql", help="run a read-only SQL query over the store",
                       description="Run one read-only SQL statement. The schema is in "
                                   "docs/store.md (tables sweeps, runs, workers). Control "
                                   "characters in the data are shown escaped (\\x1b) in "
                                   "the table and on a terminal; --csv and --json into a "
                                   "file or a pipe are exact. On PostgreSQL, $SLOPETUI_READ_DB "
                                   "names a role that only reads (docs/store.md). Exit "
                                   "status: 0 done, 1 stopped by --timeout, 2 refused or "
                                   "invalid, 130 interrupted.",
                       epilog="example: slopetui sql \"SELECT regime, count(*) FROM runs "
                              "WHERE sweep_id = 3 GROUP BY regime\"")
    p.add_argument("query", metavar="SQL", help="one SQL statement")
    fmt = p.add_mutually_exclusive_group()
    fmt.add_argument("--csv", action="store_true", help="CSV output")
    fmt.add_argument("--json", action="store_true", help="one JSON object per row")
    fmt.add_argument("--out", metavar="FILE",
                     help="write the rows to FILE, CSV or JSON by its extension (.csv, "
                          ".json: a list of objects); written whole or not at all")
    # None: the default of the output asked for (cli.sql.DEFAULT_LIMIT)
    p.add_argument("--limit", type=int, default=None, metavar="N",
                   help="print (or write to --out) at most N rows (default 1000 printed, "
                        "all written to --out; 0 for all)")
    # A string: parse_timeout's one-line error beats argparse's usage dump.
    p.add_argument("--timeout", metavar="S", default=None,
                   help=f"stop the query after S seconds of database time (default "
                        f"{DEFAULT_TIMEOUT_S:g}; 0 for no limit)")
    add_db_option(p)
