"""The one module that owns engines, sessions and transactions.

``Database(url)`` opens (and creates) a store; ``open_store(url)`` (``slopetui.store.open``)
opens it and migrates it to the current schema. Every write goes through
``Database.transaction()``; on SQLite that is a ``BEGIN IMMEDIATE`` transaction, so two
processes never both hold a read lock they then try to upgrade (that upgrade ignores
busy_timeout and fails at once with "database is locked").

A SQLite store that this process cannot write (a folder or file of another user, a
read-only file system) is opened read-only where the caller only reads
(``Database(url, read_only_ok=True)``: the commands of ``cli.options.READ_COMMANDS``,
``slopetui show``'s drawing, the notebook API), and ``Database.read_only`` says so in one
line; every write then fails with SQLite's "attempt to write a readonly database". A WAL
database needs its -shm file to be read: with ``mode=ro`` SQLite uses an existing one (a
writer has the store open) or makes one where it may (a file it cannot write, in a folder
it can). When neither works there is no -shm, so no connection has the store open (the
last one to close removes the -wal and -shm files, its transactions checkpointed into the
file): the file holds every committed transaction and is read with ``immutable=1`` (no
locks, no -shm). That read is a snapshot: a writer that opens the store afterwards
(someone who may write its folder) is not seen, and its writes may even meet a read in
progress; the note says "a snapshot". A -wal with transactions but no -shm (a writer
that crashed) needs a writer's recovery: refused, saying so.
"""

from __future__ import annotations

import os
import sqlite3
import time
from collections.abc import Iterator
from contextlib import closing, contextmanager
from datetime import datetime
from pathlib import Path
from typing import Any, cast
from urllib.parse import quote

from sqlalchemy import Connection, Engine, create_engine, event, inspect, select
from sqlalchemy.engine import URL, CursorResult, Result, make_url
from sqlalchemy.exc import ArgumentError, DBAPIError, SQLAlchemyError
from sqlalchemy.orm import Session, sessionmaker

from core.mounts import network_filesystem
from slopetui.store.connection_budget import ConnectionBudget
from slopetui.store.db_time import db_now
from slopetui.store.failures import DatabaseFailure, StoreError, describe, os_failure
from slopetui.store.location import DB_ENV, READ_DB_ENV, default_url
from slopetui.store.url_text import password_hidden

#: How long a SQLite connection waits for another writer before "database is locked" (ms).
#: A write transaction here lasts well under 10 ms; a minute covers a checkpoint on a
#: loaded disk with a wide margin.
BUSY_TIMEOUT_MS = 60_000
#: The largest value a read-only query may build (bytes). The largest stored value is a
#: sweep's spec or a run's peaks, a few kB; 16 MiB leaves room for group_concat over a
#: whole sweep of 100 000 runs.
MAX_READ_VALUE_BYTES = 16 * 1024**2
#: Execution option that marks a connection as a reader (a deferred BEGIN on SQLite).
READ_OPTION = "slopetui_read"


#: Words of the databases' own messages when the read-only connection refuses a statement
#: (SQLite mode=ro and query_only, the authorizer, PostgreSQL READ ONLY).
REFUSAL_WORDS = ("readonly", "read-only", "authoriz")


def is_refusal(message: str) -> bool:
    """Did the read-only connection refuse the statement (rather than fail on it)?"""
    return any(word in message for word in REFUSAL_WORDS)


def parse_url(url: str) -> URL:
    try:
        return make_url(url)
    except (ArgumentError, ValueError) as exc:  # ValueError: a port or IPv6 host misread;
        # the message quotes the URL: its password hidden
        raise StoreError(f"--db: {password_hidden(url)!r} is not a SQLAlchemy database URL "
                         "(e.g. sqlite:///runs.db or postgresql+psycopg://host/db)") from exc


def sqlite_path(url: URL) -> Path | None:
    """The file of a SQLite URL; None for in-memory SQLite and other databases."""
    if url.get_backend_name() != "sqlite" or url.database in (None, "", ":memory:"):
        return None
    return Path(url.database).expanduser().resolve()


def refuse_network_filesystem(path: Path) -> None:
    """A SQLite file must be on a local disk: its write-ahead log keeps an index in shared
    memory (the -shm file, mapped by every process), which a network file system does not
    share between hosts, and its locks are unsafe there (core.mounts)."""
    kind = network_filesystem(path.parent)
    if kind is not None:
        raise StoreError(
            f"{path} is on a network file system ({kind}): SQLite does not work there "
            "(its write-ahead log and locks need a local disk). Use a PostgreSQL server: "
            "--db postgresql+psycopg://HOST/DB or SLOPETUI_DB (`slopetui db serve` starts "
            "one of your own), or a SQLite file on a local disk (--db sqlite:////tmp/...)")


def unwritable(path: Path) -> str | None:
    """Why this process cannot write the existing SQLite file at ``path`` (and so cannot
    open it as a writer: WAL needs its -wal and -shm files), or None if it can."""
    folder = path.parent
    if os.statvfs(folder).f_flag & os.ST_RDONLY:
        return f"{folder} is on a read-only file system"
    if not os.access(folder, os.W_OK | os.X_OK):
        return f"no permission to write in {folder}"
    for name in (path, Path(f"{path}-wal"), Path(f"{path}-shm")):
        if name.exists() and not os.access(name, os.W_OK):
            return f"no permission to write {name}"
    return None


def read_only_uri(path: Path) -> tuple[str, bool]:
    """The URI a reader opens the unwritable store at ``path`` with, and whether it is
    immutable (the module docstring says when): ``mode=ro`` if a connection opens and
    reads with it (a -shm file exists, or can be made), else ``immutable=1`` unless a
    -wal holds transactions (StoreError: only a writer can recover them)."""
    uri = f"file:{quote(str(path))}?mode=ro"
    try:
        with closing(sqlite3.connect(uri, uri=True)) as probe:
            probe.execute("SELECT count(*) FROM sqlite_master").fetchone()
        return uri, False
    except sqlite3.Error:
        pass  # no -shm, and none can be made: SQLite cannot read the log
    wal = Path(f"{path}-wal")
    if wal.exists() and wal.stat().st_size > 0:
        raise StoreError(f"cannot read {path}: its write-ahead log {wal.name} holds "
                         "transactions that only a writer can recover (a writer stopped "
                         "without closing it); open the store once as a user who may write "
                         f"in {path.parent}")
    return uri + "&immutable=1", True


def _create_private_file(path: Path, *, make_folder: bool) -> None:
    """Create the database file readable by its owner only (SQLite gives its -wal and
    -shm files the permissions of the database file).

    make_folder : create the folder too. Only for the default store: a folder named in an
                  explicit URL that does not exist is more likely a typo than a wish, and
                  creating it would hide the typo behind an empty store.
    """
    try:
        if make_folder:
            path.parent.mkdir(parents=True, exist_ok=True, mode=0o700)
        fd = os.open(path, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o600)
    except FileExistsError:
        return
    except OSError as exc:
        raise os_failure(path, exc) from None
    os.close(fd)


def rows_changed(result: Result[Any]) -> int:
    """The rows an UPDATE or DELETE changed (what SQLAlchemy's CursorResult.rowcount says;
    Session.execute is typed as returning a plain Result)."""
    return cast("CursorResult[Any]", result).rowcount


def _write_ahead_log(cur: sqlite3.Cursor) -> None:
    """Put the file in WAL mode (a new store's first connections do; it stays so).

    The pragma reads the file, then takes its write lock; when another connection holds
    that lock (another process switching the same new store at once), SQLite answers
    "database is locked" at once, without calling the busy handler, as for any read lock
    upgraded (module docstring): 3 times in 960 connections of 16 processes opening one
    new file (a stress run, raw sqlite3), once in CI (8 processes). So it is retried here,
    for as long as busy_timeout would have waited."""
    if cur.execute("PRAGMA journal_mode").fetchone()[0] == "wal":
        return
    deadline = time.monotonic() + BUSY_TIMEOUT_MS / 1000
    pause = 0.001
    while True:
        try:
            cur.execute("PRAGMA journal_mode = WAL")  # ("memory" stays so: no loop on it)
            return
        except sqlite3.OperationalError as exc:
            if "locked" not in str(exc) or time.monotonic() > deadline:
                raise
            time.sleep(pause)
            pause = min(2 * pause, 0.05)


def _sqlite_on_connect(dbapi_connection: Any, _record: Any) -> None:
    # Let SQLAlchemy's BEGIN below be the only transaction control (pysqlite's own
    # implicit BEGIN would be deferred, see the module docstring).
    dbapi_connection.isolation_level = None
    cur = dbapi_connection.cursor()
    cur.execute(f"PRAGMA busy_timeout = {BUSY_TIMEOUT_MS}")
    cur.execute("PRAGMA foreign_keys = ON")
    _write_ahead_log(cur)
    # With WAL, NORMAL loses no committed transaction on a process crash, only possibly
    # the last ones on a power cut; FULL would fsync every claim and result.
    cur.execute("PRAGMA synchronous = NORMAL")
    cur.close()


def _sqlite_begin(conn: Any) -> None:
    # Reads (Database.sessions, Database.reader) take no lock up front: in WAL mode they
    # run beside a writer. Everything else takes the write lock at BEGIN.
    read = conn.get_execution_options().get(READ_OPTION, False)
    conn.exec_driver_sql("BEGIN" if read else "BEGIN IMMEDIATE")


#: Pragmas that take an argument and only read (SQLAlchemy's inspector uses them).
READ_PRAGMAS = frozenset({"table_info", "table_xinfo", "index_list", "index_info",
                          "index_xinfo", "foreign_key_list", "table_list"})


def _read_only_authorizer(action: int, arg1: str | None, arg2: str | None, *_: Any) -> int:
    """mode=ro still lets ATTACH create a new file and PRAGMA turn query_only off, and
    a few SQL functions leak or act rather than compute (checked when a statement is
    prepared, so also inside views)."""
    if action in (sqlite3.SQLITE_ATTACH, sqlite3.SQLITE_DETACH):
        return sqlite3.SQLITE_DENY
    if action == sqlite3.SQLITE_PRAGMA and arg2 is not None and arg1 not in READ_PRAGMAS:
        return sqlite3.SQLITE_DENY  # setting a pragma, not reading one
    # SQLITE_FUNCTION: arg2 is the function's name (Python >= 3.11), as typed.
    # fts3_tokenizer(name) returns a tokenizer's memory address (defeats ASLR) and with
    # two arguments installs one (code execution where enabled); load_extension loads a
    # shared library (Python's sqlite3 disables it by default: refused here as well);
    # sqlite_log writes to the process's SQLite error log; rtreenode and rtreedepth are
    # rtree's debugging functions that decode arbitrary blobs (CVE-2019-8457). The rest
    # of SQLite's built-ins compute values only; zeroblob/randomblob/printf can ask for
    # up to SQLITE_LIMIT_LENGTH (1e9) bytes, which no authorizer can see.
    if action == sqlite3.SQLITE_FUNCTION and arg2 is not None and arg2.lower() in {
            "fts3_tokenizer", "load_extension", "sqlite_log", "rtreenode", "rtreedepth"}:
        return sqlite3.SQLITE_DENY
    return sqlite3.SQLITE_OK


def _sqlite_read_only_connect(dbapi_connection: Any, _record: Any) -> None:
    dbapi_connection.isolation_level = None
    cur = dbapi_connection.cursor()
    cur.execute(f"PRAGMA busy_timeout = {BUSY_TIMEOUT_MS}")
    cur.execute("PRAGMA query_only = ON")  # second guard behind mode=ro
    cur.close()
    dbapi_connection.set_authorizer(_read_only_authorizer)
    # zeroblob(1e9), randomblob(), printf('%.*c', ...) build values of up to SQLite's
    # default 1 GB in one step, which neither the authorizer nor the time limit sees
    dbapi_connection.setlimit(sqlite3.SQLITE_LIMIT_LENGTH, MAX_READ_VALUE_BYTES)


def _postgres_read_only_begin(conn: Any) -> None:
    conn.exec_driver_sql("SET TRANSACTION READ ONLY")


def _budget(engine: Engine, slots: ConnectionBudget) -> None:
    """Open the engine's connections only under a slot of ``slots`` (acquired before the
    connection is made, released once it is closed, or if making it failed)."""

    @event.listens_for(engine, "do_connect")
    def _connect(dialect: Any, record: Any, cargs: Any, cparams: Any) -> Any:
        slots.acquire()
        try:
            connection = dialect.connect(*cargs, **cparams)
        except BaseException:
            slots.release()
            raise
        record.info["slot"] = True
        return connection

    def _closed(_dbapi: Any, record: Any) -> None:
        if record is not None and record.info.pop("slot", False):
            slots.release()

    event.listen(engine, "close", _closed)


class Database:
    """A store at ``url`` (default: ``default_url()``), at whatever schema it has: nothing
    is migrated here. ``open_store`` (``slopetui.store.open``) opens one and migrates it;
    ``Database`` alone is for the tools that inspect or change an old schema
    (``slopetui db``), and for the workers, whose pool migrated the store before it
    spawned them.
    """

    def __init__(self, url: str | None = None, *, slots: ConnectionBudget | None = None,
                 read_only_ok: bool = False) -> None:
        """slots : a connection budget shared with other processes (a worker pool's, see
                   slopetui.ops.connection_slots): this process opens a connection only
                   while it holds a slot, and ``idle()`` closes it again. None: no budget
                   (SQLite, the application, the commands).
        read_only_ok : the caller only reads: a SQLite file it cannot write is opened
                   read-only (module docstring) rather than refused; ``read_only`` then
                   says so."""
        explicit = url or os.environ.get(DB_ENV)
        self.slots = slots
        self.url = parse_url(explicit or default_url())
        self.path = sqlite_path(self.url)
        #: None, or the one line that says the store was opened for reading only, and why.
        self.read_only: str | None = None
        #: Why this process cannot write the store, when it was opened read-only.
        self.unwritable: str | None = None
        #: The URI of a store opened read-only (every connection of this Database uses it).
        self._read_only_uri: str | None = None
        if self.path is not None:
            refuse_network_filesystem(self.path)
            why = unwritable(self.path) if read_only_ok and self.path.is_file() else None
            if why is None:
                _create_private_file(self.path, make_folder=not explicit)
            else:
                self._read_only_uri, snapshot = read_only_uri(self.path)
                self.unwritable = why
                self.read_only = (f"store is read-only ({why}): opened for reading"
                                  + (", as a snapshot (no writer has it open)" if snapshot
                                     else ""))
            self.url = self.url.set(database=str(self.path))
        self.engine = self._make_engine()
        #: The same pool, for reads: ``with db.reader.connect() as conn``.
        self.reader = self.engine.execution_options(**{READ_OPTION: True})
        self._read_sessions = sessionmaker(self.reader, expire_on_commit=False)
        self._write_sessions = sessionmaker(self.engine, expire_on_commit=False)
        #: The schema revision the store was at when opened (None: no schema yet), read
        #: once: open_store compares it with the head before it pays for Alembic.
        self.opened_revision = self._first_read()

    def stored_revision(self) -> str | None:
        """The schema revision the store is at, read in plain SQL (None: no schema yet)."""
        with self.reader.connect() as conn:
            if not inspect(conn).has_table("alembic_version"):
                return None
            return conn.exec_driver_sql("SELECT version_num FROM alembic_version").scalar()

    @property
    def is_sqlite(self) -> bool:
        return self.url.get_backend_name() == "sqlite"

    def _make_engine(self) -> Engine:
        options: dict[str, Any] = {}
        if self.url.get_backend_name() == "postgresql":
            connect: dict[str, str] = {}
            if "application_name" not in self.url.query:
                # pg_stat_activity then tells which process holds which connection
                connect["application_name"] = f"slopetui pid {os.getpid()}"
            if "options" not in self.url.query:
                # the session's zone is UTC: the timestamps are "without time zone" and hold
                # UTC (db_time), but CURRENT_TIMESTAMP, the created_at defaults, would give
                # the server's local time on a server whose TimeZone is not UTC
                connect["options"] = "-c TimeZone=UTC"
            options["connect_args"] = connect
        if self._read_only_uri is not None:
            uri = self._read_only_uri
            options["creator"] = lambda: sqlite3.connect(uri, uri=True, check_same_thread=False)
        try:
            engine = create_engine(self.url, **options)
        except Exception as exc:  # a missing driver, a bad option: say which URL
            raise StoreError(f"cannot open database {self.display_url}: {exc}") from exc
        if self._read_only_uri is not None:  # no journal_mode to set: it cannot write
            event.listen(engine, "connect", _sqlite_read_only_connect)
            event.listen(engine, "begin", _sqlite_begin)
        elif self.is_sqlite:
            event.listen(engine, "connect", _sqlite_on_connect)
            event.listen(engine, "begin", _sqlite_begin)
        if self.slots is not None:
            _budget(engine, self.slots)
        return engine

    def idle(self) -> None:
        """Close the connections kept for reuse: this process will not use the store for a
        while (it computes or sleeps), and under a budget (``slots``) its slot goes back
        to the other processes. Statements after it simply open a connection again."""
        if self.slots is not None and self.slots.held:
            self.engine.dispose(close=True)

    def _first_read(self) -> str | None:
        """The stored revision, read now: the first connection and the first read of the
        file, so that a SQLite file that cannot be used (not a database, a read-only folder
        for its -wal file...) fails here with its cause named, not at a later query with
        "unable to open database file"."""
        if self.path is None:
            with self.failures_translated():
                return self.stored_revision()
        try:
            return self.stored_revision()
        except DBAPIError as exc:
            raise StoreError(describe(self.path, str(exc.orig).strip())) from None

    @property
    def display_url(self) -> str:
        """The URL for messages and logs: its password hidden, in the query too."""
        return password_hidden(self.url.render_as_string(hide_password=True))

    @contextmanager
    def failures_translated(self) -> Iterator[None]:
        """SQLAlchemy's errors in the block raised again as DatabaseFailure, naming this
        store and the cause (Optuna's ``_create_scoped_session`` does the same)."""
        try:
            yield
        except SQLAlchemyError as exc:
            reason = str(getattr(exc, "orig", None) or exc).strip()
            raise DatabaseFailure(describe(self.path, reason) if self.path is not None else
                                  f"{self.display_url}: {reason}") from exc

    @contextmanager
    def sessions(self) -> Iterator[Session]:
        """A session for reading (``with db.sessions() as s``); writes use transaction()."""
        with self.failures_translated(), self._read_sessions() as session:
            yield session

    @contextmanager
    def read(self) -> Iterator[Connection]:
        """A Core connection for reading, in one transaction: one snapshot for every
        statement in the block."""
        with self.failures_translated(), self.reader.connect() as conn:
            yield conn

    @contextmanager
    def transaction(self) -> Iterator[Session]:
        """A session in one write transaction: committed on exit, rolled back on error."""
        with self.failures_translated(), self._write_sessions.begin() as session:
            yield session

    @contextmanager
    def connection(self) -> Iterator[Connection]:
        """A Core connection in one write transaction, for prebuilt hot-path statements."""
        with self.failures_translated(), self.engine.begin() as conn:
            yield conn

    def now(self, session: Session) -> datetime:
        """Database time. Leases and heartbeats use it, so that workers on hosts whose
        clocks disagree still agree on when a lease expired."""
        now = session.scalar(select(db_now()))
        assert now is not None  # a SELECT of a function always returns its row
        return now

    def reader_url(self) -> URL:
        """The URL the read-only queries of a PostgreSQL store connect with: that of
        ``$SLOPETUI_READ_DB`` (a role that only reads, slopetui.ops.local_server) when it
        names this store's database (same host, port and database), else the store's own.
        Another database's reader is not used: its rows would be shown as this store's."""
        named = os.environ.get(READ_DB_ENV)
        if not named:
            return self.url
        reader = parse_url(named)

        def where(url: URL) -> tuple[object, ...]:
            return (url.get_backend_name(), url.host, url.port or 5432, url.database,
                    url.query.get("host"), url.query.get("port"))

        return reader if where(reader) == where(self.url) else self.url

    def read_only_engine(self) -> Engine:
        """An engine on which the database itself refuses writes: SQLite opened with
        mode=ro (plus query_only), PostgreSQL in READ ONLY transactions under the reading
        role when there is one (``reader_url``), its statements checked first
        (``slopetui.store.pg_read_guard``, in ``read_query``)."""
        backend = self.url.get_backend_name()
        if backend == "sqlite":
            if self.path is None:
                raise StoreError("read-only queries need a SQLite file, not :memory:")
            uri = self._read_only_uri or f"file:{quote(str(self.path))}?mode=ro"
            engine = create_engine("sqlite://", creator=lambda: sqlite3.connect(
                uri, uri=True, check_same_thread=False))
            event.listen(engine, "connect", _sqlite_read_only_connect)
            return engine
        if backend == "postgresql":
            engine = create_engine(self.reader_url())
            event.listen(engine, "begin", _postgres_read_only_begin)
            return engine
        raise StoreError(f"read-only queries are supported on SQLite and PostgreSQL, "
                         f"not {backend}")

    def dispose(self) -> None:
        self.engine.dispose()
