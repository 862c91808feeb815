"""Can the store be written? A probe before a pool spends its warm-up (a pool on a
read-only store compiled kernels for 19 s, then its workers died with tracebacks), and the
one line for a write the store refused in the middle of a run.

The probe runs, in one write transaction, an UPDATE of no row on each table a worker
writes. A zero-row UPDATE is refused where any write would be: SQLite on a read-only file
("attempt to write a readonly database": a file it could open only for reading, a
read-only mount, chattr +i, a file of another user), PostgreSQL in a read-only
transaction (default_transaction_read_only, a hot standby) or for a role without the
privilege. It changes nothing, so its commit writes nothing. SQLite's BEGIN IMMEDIATE
alone is not a probe: in WAL mode it takes its lock in the -shm file and succeeds on a
read-only database file; the refusal comes at the first write.

A full disk shows only when a write needs room: on SQLite the probe also asks for a
little free space beside the file.
"""

from __future__ import annotations

from sqlalchemy import update
from sqlalchemy.exc import DBAPIError

from slopetui.store.database import Database
from slopetui.store.failures import FULL_WORDS, MIN_FREE_BYTES, DatabaseFailure, describe, free_bytes
from slopetui.store.models import Run, Worker

#: Words of the databases' messages for a write they refuse, whatever is retried.
REFUSAL_WORDS = ("readonly", "read-only", "disk i/o error", *FULL_WORDS)
#: PostgreSQL's codes for the same (SQLSTATE): read_only_sql_transaction,
#: insufficient_privilege, disk_full.
REFUSAL_CODES = frozenset({"25006", "42501", "53100"})


def _reason(exc: DBAPIError) -> str:
    lines = str(exc.orig).strip().splitlines()
    return lines[0] if lines else type(exc.orig).__name__


def write_refusal(db: Database, exc: BaseException) -> str | None:
    """One line if ``exc`` is the store refusing a write (read-only, full disk, no
    privilege): retrying cannot help until someone fixes it. None for any other error."""
    if isinstance(exc, DatabaseFailure):  # Database's own (failures_translated)
        exc = exc.__cause__ or exc
    if not isinstance(exc, DBAPIError):
        return None
    reason = _reason(exc)
    code = getattr(exc.orig, "sqlstate", None)
    if code not in REFUSAL_CODES and not any(w in reason.lower() for w in REFUSAL_WORDS):
        return None
    if db.path is not None:
        return describe(db.path, reason)
    return f"cannot write the database {db.display_url}: {reason}"


def refuses_writes(db: Database) -> str | None:
    """Why the store cannot take a worker's writes (one line), or None if it can (see
    the module docstring)."""
    if db.path is not None:
        free = free_bytes(db.path)
        if free is not None and free < MIN_FREE_BYTES:
            return (f"cannot write {db.path}: the disk is full ({free // 1024} kB free "
                    f"in {db.path.parent})")
    try:
        with db.transaction() as s:
            s.execute(update(Run).where(Run.id.is_(None)).values(status=Run.status))
            s.execute(update(Worker).where(Worker.id.is_(None)).values(pid=Worker.pid))
    except DatabaseFailure as exc:
        line = write_refusal(db, exc)
        if line is None:
            raise
        return line
    return None
