"""``slopetui sql "SELECT ..."``: read-only queries of the store.

The database refuses writes itself (SQLite opened with mode=ro, query_only and an
authorizer; PostgreSQL in READ ONLY transactions); the text is not parsed here.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import sys

from sqlalchemy.exc import DBAPIError

from slopetui.cli.options import UsageError, add_db_option, open_db
from slopetui.store.database import is_refusal


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("sql", help="run a read-only SQL query over the store",
                       description="Run one read-only SQL statement. The schema is in the "
                                   "README (tables sweeps, runs, workers).",
                       epilog="example: slopetui sql \"SELECT regime, count(*) FROM runs "
                              "WHERE sweep_id = 3 GROUP BY regime\"")
    p.add_argument("query", metavar="SQL", help="one SQL statement")
    fmt = p.add_mutually_exclusive_group()
    fmt.add_argument("--csv", action="store_true", help="CSV output")
    fmt.add_argument("--json", action="store_true", help="one JSON object per row")
    p.add_argument("--limit", type=int, default=1000, metavar="N",
                   help="print at most N rows (default 1000; 0 for all)")
    add_db_option(p)
    p.set_defaults(handler=handle)


def _text(value: object) -> str:
    if value is None:
        return "NULL"
    if isinstance(value, float):
        return f"{value:.6g}"
    return str(value)


def _table(columns: list[str], rows: list[tuple[object, ...]]) -> str:
    cells = [[_text(v) for v in row] for row in rows]
    widths = [max([len(c), *(len(r[i]) for r in cells)]) for i, c in enumerate(columns)]
    line = lambda values: "  ".join(v.ljust(w) for v, w in zip(values, widths)).rstrip()
    return "\n".join([line(columns), line(["-" * w for w in widths]), *map(line, cells)])


def _json_value(value: object) -> object:
    return None if isinstance(value, float) and not math.isfinite(value) else value


def handle(args: argparse.Namespace) -> int:
    if args.limit < 0:
        raise UsageError(f"--limit must be >= 0, got {args.limit}")
    engine = open_db(args).read_only_engine()
    try:
        with engine.connect() as conn:
            result = conn.exec_driver_sql(args.query)
            if not result.returns_rows:
                print("(no rows: the statement returns nothing)")
                return 0
            columns = list(result.keys())
            rows = [tuple(r) for r in (result.fetchmany(args.limit) if args.limit
                                       else result.fetchall())]
            more = args.limit and result.fetchone() is not None
    except DBAPIError as exc:
        message = str(exc.orig).strip()
        if is_refusal(message):
            print(f"slopetui sql: refused: the store is opened read-only ({message})",
                  file=sys.stderr)
        else:
            print(f"slopetui sql: error: {message}", file=sys.stderr)
        return 2
    finally:
        engine.dispose()
    if args.csv:
        writer = csv.writer(sys.stdout, lineterminator="\n")
        writer.writerow(columns)
        writer.writerows(rows)
    elif args.json:
        for row in rows:
            print(json.dumps({c: _json_value(v) for c, v in zip(columns, row)}, default=str))
    else:
        print(_table(columns, rows))
        print(f"({len(rows)} row{'s' if len(rows) != 1 else ''}"
              f"{'; more not shown, see --limit' if more else ''})")
    return 0
