"""What a read-only query may not do on PostgreSQL although a READ ONLY transaction lets it
(``slopetui sql`` and the application's console; ``read_query`` calls ``refusal`` before
a statement runs).

A READ ONLY transaction refuses writes to tables, nothing else: ``pg_terminate_backend``
and ``pg_cancel_backend`` (allowed to any role on the backends of its own role, and the
console connects as the workers' role), the advisory locks (a session lock outlives the
statement on the pooled connection, and the workers and migrations wait on such locks),
NOTIFY, ``set_config``, a DO block (PL/pgSQL, which can build any call from pieces), COPY
TO PROGRAM or a server file (a superuser), and functions that run a query given as text
(``query_to_xml``, ``ts_stat``) all pass. So, before the statement runs:

- it must begin with a keyword that only reads: SELECT, WITH, VALUES, TABLE, EXPLAIN,
  SHOW (or a parenthesis), after any comments;
- it may not name a function of ``REFUSED_FUNCTIONS`` anywhere (in a string or a comment
  too: a false alarm costs a rephrased query, a miss costs the workers), nor a Unicode
  escaped identifier (``U&"..."``, which could spell one).

This is a list, and a list can miss: a function that an owner of the store created (with
the workers' role, which may create functions) and that calls these is not seen. The
boundary that misses nothing is a role of its own with SELECT only, which cannot signal
the workers' backends nor take their locks: ``slopetui db serve`` makes one
(``slopetui_read``, DIR/read-url) and docs/store.md says how to make one on another
server; ``SLOPETUI_READ_DB`` names its URL to the commands that only read.
"""

from __future__ import annotations

import re

#: The first keyword of a statement that only reads.
READING_KEYWORDS = frozenset({"select", "with", "values", "table", "explain", "show"})

#: Functions that act on other sessions, hold locks past the statement, change settings,
#: reach the server's files or programs, or run SQL given as text. Prefixes end in "_".
REFUSED_FUNCTIONS = (
    "pg_terminate_backend", "pg_cancel_backend", "pg_signal_backend",
    "pg_advisory_", "pg_try_advisory_",
    "pg_notify", "set_config",
    "pg_reload_conf", "pg_rotate_logfile", "pg_promote", "pg_switch_wal",
    "pg_log_backend_memory_contexts", "pg_create_", "pg_drop_replication_slot",
    "pg_replication_", "pg_logical_", "pg_backup_", "pg_start_backup", "pg_stop_backup",
    "pg_read_file", "pg_read_binary_file", "pg_ls_", "pg_stat_file", "pg_file_",
    "lo_import", "lo_export",
    "query_to_xml", "cursor_to_xml", "ts_stat", "ts_rewrite",
    "dblink",
)

_COMMENTS = re.compile(r"\s+|--[^\n]*(?:\n|$)|/\*.*?\*/", re.DOTALL)
_FUNCTION = re.compile(r"(?<![a-z0-9_$])(" + "|".join(
    re.escape(name) + (r"[a-z0-9_$]*" if name.endswith("_") else r"(?![a-z0-9_$])")
    for name in REFUSED_FUNCTIONS) + ")")
_UNICODE_IDENTIFIER = re.compile(r"u&\"")


def _first_word(sql: str) -> str | None:
    """The statement's first keyword (lower case; "(" for a parenthesis), past leading
    whitespace and comments; None when there is nothing else (the server runs nothing)."""
    position = 0
    while match := _COMMENTS.match(sql, position):
        if match.end() == position:
            break
        position = match.end()
    if position == len(sql):
        return None
    if sql[position:position + 1] == "(":
        return "("
    word = re.match(r"[A-Za-z_]+", sql[position:])
    return word.group(0).lower() if word else ""


def refusal(sql: str) -> str | None:
    """Why a read-only query may not run ``sql`` on PostgreSQL (one line), or None."""
    first = _first_word(sql)
    if first is not None and first != "(" and first not in READING_KEYWORDS:
        shown = first.upper() or "this statement"
        return (f"{shown} is not a query: a read-only query begins with "
                f"{', '.join(sorted(k.upper() for k in READING_KEYWORDS))}")
    lowered = sql.lower()
    if found := _FUNCTION.search(lowered):
        return (f"{found.group(1)}() acts beyond a read (other sessions, locks, settings, "
                "the server's files, SQL given as text): a read-only query may not call it")
    if _UNICODE_IDENTIFIER.search(lowered):
        return 'a Unicode escaped identifier (U&"...") could name any function: write it plainly'
    return None
